//! Fuzzes what vito reads with generated and mutated inputs (`vito::fuzz`): problem files,
//! URDFs, deep expressions, long chains, many attributes, trajectory CSVs. Usage:
//! `cargo run --release --example fuzz -- [COUNT] [SEED] [FIRST]` (default 1,000,000
//! inputs, seed 1, from input 0; FIRST runs inputs FIRST..COUNT of the run alone: each input has its own generator), or
//! `make fuzz`. Prints `next input N` every 1,000 inputs (after an abort, the last one is the
//! FIRST to repeat from), the figures every 10,000 and at the end, per kind with its slowest
//! input; exits 1 if any input panicked or took more than 10 s of CPU time, writing the first few to
//! `fuzz-panics/`.

use std::io::Write;
use std::path::Path;

fn main() -> std::process::ExitCode {
    let mut args = std::env::args().skip(1);
    let count: u64 = args
        .next()
        .and_then(|a| a.parse().ok())
        .unwrap_or(1_000_000);
    let seed: u64 = args.next().and_then(|a| a.parse().ok()).unwrap_or(1);
    let first: u64 = args.next().and_then(|a| a.parse().ok()).unwrap_or(0);
    let problems = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems");
    let seeds = match vito::fuzz::seeds(&problems) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("cannot read the seeds in {}: {e}", problems.display());
            return std::process::ExitCode::from(2);
        }
    };
    // Panics are counted; the first few are printed with their place.
    let printed = std::sync::atomic::AtomicUsize::new(0);
    std::panic::set_hook(Box::new(move |info| {
        if printed.fetch_add(1, std::sync::atomic::Ordering::Relaxed) < 10 {
            eprintln!("panic: {info}");
        }
    }));
    let print = |r: &vito::fuzz::FuzzReport| {
        println!(
            "inputs {} accepted {} panics {} hangs>{}s {} wall {:.1} s slowest {:.3} ms CPU ({})",
            r.inputs,
            r.accepted,
            r.panics,
            vito::fuzz::HANG.as_secs(),
            r.hangs,
            r.wall.as_secs_f64(),
            r.slowest.0.as_secs_f64() * 1e3,
            r.slowest.1
        );
        for k in &r.kinds {
            println!(
                "  {:<10} inputs {:>8} accepted {:>8} panics {} hangs {} mean {:>7.3} ms slowest {:>9.3} ms CPU (input {}, {})",
                k.kind.name(),
                k.inputs,
                k.accepted,
                k.panics,
                k.hangs,
                k.total.as_secs_f64() * 1e3 / k.inputs.max(1) as f64,
                k.slowest.0.as_secs_f64() * 1e3,
                k.slowest.1,
                k.slowest.2
            );
        }
    };
    println!(
        "{} seeds, inputs {first}..{count}, seed {seed}",
        seeds.len()
    );
    let report = vito::fuzz::run(&seeds, first..count, seed, vito::fuzz::Sizes::Full, |r| {
        println!("next input {}", r.next);
        if r.inputs.is_multiple_of(10_000) {
            print(r);
        }
        let _ = std::io::stdout().flush();
    });
    print(&report);
    if report.panics == 0 && report.hangs == 0 {
        return std::process::ExitCode::SUCCESS;
    }
    let _ = std::fs::create_dir_all("fuzz-panics");
    for (what, input) in &report.saved {
        eprintln!(
            "{what}: input {} ({}, from {})",
            input.index,
            input.kind.name(),
            input.seed
        );
        for (name, text) in input.files() {
            let _ = std::fs::write(format!("fuzz-panics/{}-{what}-{name}", input.index), text);
        }
    }
    std::process::ExitCode::FAILURE
}
