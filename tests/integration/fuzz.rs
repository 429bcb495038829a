//! A short run of the fuzz harness (`vito::fuzz`; the long run is `make fuzz`):
//! mutated problem files and URDFs end in a result or an error, never a panic.

use std::path::Path;

#[test]
fn mutated_inputs_never_panic() {
    let problems = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems");
    let seeds = vito::fuzz::seeds(&problems).unwrap();
    assert!(seeds.len() >= 10, "{} seeds", seeds.len());
    let report = vito::fuzz::run(&seeds, 0..3000, 11, |_| {});
    assert_eq!(report.inputs, 3000);
    assert_eq!(
        report.panics, 0,
        "first panicking inputs: {:?}",
        report.panic_inputs
    );
    // Mutation keeps some inputs valid and makes most invalid: both paths are exercised.
    assert!(
        report.accepted > 100 && report.accepted < 2900,
        "{}",
        report.accepted
    );
}
