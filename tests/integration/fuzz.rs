//! A short run of the fuzz harness (`vito::fuzz`, small sizes; the long run is `make fuzz`):
//! every kind of input (mutated problem files and URDFs, deep expressions, generated chains,
//! many attributes, mutated trajectory CSVs) ends in a result or an error, never a panic.

use std::path::Path;

#[test]
fn mutated_inputs_never_panic() {
    let problems = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems");
    let seeds = vito::fuzz::seeds(&problems).unwrap();
    assert!(seeds.len() >= 10, "{} seeds", seeds.len());
    let report = vito::fuzz::run(&seeds, 0..3000, 11, vito::fuzz::Sizes::Small, |_| {});
    assert_eq!(report.inputs, 3000);
    assert_eq!(
        report.panics,
        0,
        "first panicking inputs: {:?}",
        report
            .saved
            .iter()
            .map(|(what, i)| (what, i.index, i.kind.name(), &i.seed))
            .collect::<Vec<_>>()
    );
    for k in &report.kinds {
        assert!(
            k.inputs > 50 && k.accepted > 0 && k.accepted < k.inputs,
            "{} inputs of kind {}, {} accepted",
            k.inputs,
            k.kind.name(),
            k.accepted
        );
    }
    // Mutation keeps some inputs valid and makes most invalid: both paths are exercised.
    assert!(
        report.accepted > 100 && report.accepted < 2900,
        "{}",
        report.accepted
    );
}
