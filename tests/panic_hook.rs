//! The panic hook that keeps a caught urdf-rs panic quiet hides nothing else. Its own test
//! binary: the hook is process-wide, installed on the first URDF parse.

use std::panic::{catch_unwind, set_hook};
use std::sync::atomic::{AtomicUsize, Ordering};

use faze4::model::{PackagePaths, urdf};

static REPORTED: AtomicUsize = AtomicUsize::new(0);

#[test]
fn parser_panics_are_quiet_and_other_panics_are_not() {
    // stands for the default hook (or libFuzzer's): counts what it is shown
    set_hook(Box::new(|_| {
        REPORTED.fetch_add(1, Ordering::SeqCst);
    }));
    let panicking = r#"<" xmlns="N":=""/>"#;
    for _ in 0..2 {
        let e = urdf::read_str(panicking, "p.urdf", None, &PackagePaths::default()).unwrap_err();
        assert!(e.to_string().contains("urdf-rs panicked"), "{e}");
    }
    assert_eq!(REPORTED.load(Ordering::SeqCst), 0, "a caught parser panic was reported");

    // a panic outside the parser, on this thread and on another, reaches the previous hook
    assert!(catch_unwind(|| panic!("genuine")).is_err());
    assert!(std::thread::spawn(|| panic!("genuine, elsewhere")).join().is_err());
    assert_eq!(REPORTED.load(Ordering::SeqCst), 2);
}
