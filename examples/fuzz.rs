//! Fuzzes problem loading and URDF loading with the project's own files, mutated
//! (`vito::fuzz`). Usage: `cargo run --release --example fuzz -- [COUNT] [SEED]
//! [FIRST]` (default 1,000,000 inputs, seed 1, from input 0; FIRST repeats the end of a run),
//! or `make fuzz`. Prints the figures; exits 1 if any input panicked, printing where and
//! writing the first few inputs to `fuzz-panics/`.

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
            "inputs {} accepted {} panics {} wall {:.1} s slowest {:.3} ms ({})",
            r.inputs,
            r.accepted,
            r.panics,
            r.wall.as_secs_f64(),
            r.slowest.0.as_secs_f64() * 1e3,
            r.slowest.1
        );
    };
    println!("{} seeds, {count} inputs, seed {seed}", seeds.len());
    let report = vito::fuzz::run(&seeds, first..count, seed, |r| {
        if r.inputs % 100_000 == 0 {
            print(r);
        }
    });
    print(&report);
    if report.panics == 0 {
        return std::process::ExitCode::SUCCESS;
    }
    let _ = std::fs::create_dir_all("fuzz-panics");
    for (i, (name, problem, urdf)) in report.panic_inputs.iter().enumerate() {
        eprintln!("panic {i}: from {name}");
        if let Some(p) = problem {
            let _ = std::fs::write(format!("fuzz-panics/{i}.toml"), p);
        }
        let _ = std::fs::write(format!("fuzz-panics/{i}.urdf"), urdf);
    }
    std::process::ExitCode::FAILURE
}
