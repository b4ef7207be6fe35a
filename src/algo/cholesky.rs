//! In-place Cholesky factorisation and solve, without allocation.

use nalgebra::{DMatrix, DVector};

/// Factors the symmetric positive-definite `a` into `l` (lower triangle, `a = L Lᵀ`); only
/// the lower triangle of `a` is read. The diagonal of `l` holds the reciprocals `1 / L_jj`, so
/// that neither the factor nor [`cholesky_solve`] divides more than once per column (a
/// division's latency is several multiplications', and here each one waits for the last).
/// Fails if `a` is not positive definite (or not finite) with the column j whose pivot
/// `A_jj − Σ_k L_jk²` is not positive, and that pivot; `l` is then unspecified.
pub fn cholesky_factor(a: &DMatrix<f64>, l: &mut DMatrix<f64>) -> Result<(), (usize, f64)> {
    let n = a.nrows();
    // column-major storage: entry (i, j) is at i + j·n
    let a = a.as_slice();
    let l = l.as_mut_slice();
    for j in 0..n {
        // L_jj = sqrt(A_jj − Σ_k L_jk²)
        let mut d = a[j + j * n];
        for k in 0..j {
            d -= l[j + k * n] * l[j + k * n];
        }
        if d.is_nan() || d <= 0.0 {
            return Err((j, d));
        }
        let inv_ljj = 1.0 / d.sqrt();
        l[j + j * n] = inv_ljj;
        // L_ij = (A_ij − Σ_k L_ik L_jk) / L_jj, i > j
        for i in j + 1..n {
            let mut s = a[i + j * n];
            for k in 0..j {
                s -= l[i + k * n] * l[j + k * n];
            }
            l[i + j * n] = s * inv_ljj;
        }
    }
    Ok(())
}

/// Solves `L Lᵀ x = b` in place (`b` becomes x), with `l` from [`cholesky_factor`] (its
/// diagonal holding `1 / L_ii`).
pub fn cholesky_solve(l: &DMatrix<f64>, b: &mut DVector<f64>) {
    let n = l.nrows();
    let l = l.as_slice();
    let b = b.as_mut_slice();
    // forward substitution: L y = b
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i + k * n] * b[k];
        }
        b[i] = s * l[i + i * n];
    }
    // back substitution: Lᵀ x = y
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= l[k + i * n] * b[k];
        }
        b[i] = s * l[i + i * n];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_symmetric_positive_definite_system() {
        let a = DMatrix::from_row_slice(3, 3, &[4.0, 1.0, 0.5, 1.0, 3.0, -0.2, 0.5, -0.2, 2.0]);
        let x = DVector::from_vec(vec![0.3, -1.0, 2.0]);
        let mut b = &a * &x;
        let mut l = DMatrix::zeros(3, 3);
        assert!(cholesky_factor(&a, &mut l).is_ok());
        cholesky_solve(&l, &mut b);
        assert!((b - x).amax() < 1e-15);
        let not_pd = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        assert_eq!(cholesky_factor(&not_pd, &mut DMatrix::zeros(2, 2)), Err((1, -3.0)));
    }
}
