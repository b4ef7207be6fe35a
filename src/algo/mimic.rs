//! Mimic joints: the body-level algorithms on the coordinates.
//!
//! With `<mimic>` joints the bodies' positions are `q_b = G q + o` (G nb×n, one entry m per
//! row: [`crate::model::Body`]), their velocities and accelerations `G v`, `G v̇` (o is
//! constant). The algorithms run unchanged on the bodies, into `Data`'s body twins, and their
//! results are reduced to the coordinates by virtual work: `τ = Gᵀ τ_b`, `g = Gᵀ g_b`,
//! `C v = Gᵀ (C v)_b`, `M = Gᵀ M_b G` (docs/model.md 1.5).

use std::mem::{swap, take};

use super::Data;
use crate::model::Model;

/// Which of the coordinates' terms a body-level pass produces.
#[derive(Clone, Copy)]
pub(crate) struct Terms {
    pub tau: bool,
    pub g: bool,
    pub bias: bool,
    pub m: bool,
}

/// Runs `pass` on the bodies: q (and qd, qdd where given) expanded to the bodies, `data.tau`,
/// `g`, `bias` and `m` swapped for their body-sized twins (a pointer swap, no allocation), then
/// swapped back and the `terms` asked for reduced. Only for a model with mimic joints.
pub(crate) fn on_bodies(
    model: &Model,
    data: &mut Data,
    (q, qd, qdd): (&[f64], Option<&[f64]>, Option<&[f64]>),
    terms: Terms,
    pass: impl FnOnce(&Model, &mut Data, &[f64], Option<&[f64]>, Option<&[f64]>),
) {
    debug_assert!(model.has_mimic());
    let (mut qb, mut qdb, mut qddb) = (
        take(&mut data.body.q),
        take(&mut data.body.qd),
        take(&mut data.body.qdd),
    );
    model.expand_positions(q, &mut qb);
    if let Some(qd) = qd {
        model.expand_velocities(qd, &mut qdb);
    }
    if let Some(qdd) = qdd {
        model.expand_velocities(qdd, &mut qddb);
    }
    swap_terms(data);
    pass(model, data, &qb, qd.map(|_| &qdb[..]), qdd.map(|_| &qddb[..]));
    swap_terms(data);
    (data.body.q, data.body.qd, data.body.qdd) = (qb, qdb, qddb);
    let body = &data.body;
    if terms.tau {
        model.reduce_forces(body.tau.as_slice(), data.tau.as_mut_slice());
    }
    if terms.g {
        model.reduce_forces(body.g.as_slice(), data.g.as_mut_slice());
    }
    if terms.bias {
        model.reduce_forces(body.bias.as_slice(), data.bias.as_mut_slice());
    }
    if terms.m {
        model.reduce_matrix(&body.m, &mut data.m);
    }
}

fn swap_terms(data: &mut Data) {
    swap(&mut data.tau, &mut data.body.tau);
    swap(&mut data.g, &mut data.body.g);
    swap(&mut data.bias, &mut data.body.bias);
    swap(&mut data.m, &mut data.body.m);
}
