//! `vito view`: the animation page (and a strip as SVG) of existing result directories.

use std::path::{Path, PathBuf};

use vito::problem::{LoadedProblem, load};

use super::args::parse_overrides;
use super::error::CliError;
use super::output::print_model_warnings;

/// Most poses in a strip (`--strip`).
const MAX_STRIP_POSES: usize = 1000;

/// A result directory read back: its summary and trajectory file.
struct Result_ {
    dir: PathBuf,
    summary: serde_json::Value,
    csv: String,
}

fn read_result(dir: &Path) -> Result<Result_, CliError> {
    use vito::files::input::{MAX_TEXT_BYTES, MAX_TRAJECTORY_BYTES, read_regular_text};
    let read = |name: &str, max_bytes: u64| {
        let path = dir.join(name);
        read_regular_text(&path, max_bytes).map_err(|e| {
            CliError::Input(format!(
                "{}: {e}; give a directory `vito solve`, `vito simulate` or a sweep run wrote",
                path.display()
            ))
        })
    };
    let summary = read("summary.json", MAX_TEXT_BYTES)?;
    let summary = serde_json::from_str(&summary).map_err(|e| {
        CliError::Input(format!(
            "{}: not JSON ({e})",
            dir.join("summary.json").display()
        ))
    })?;
    Ok(Result_ {
        dir: dir.to_owned(),
        summary,
        csv: read("trajectory.csv", MAX_TRAJECTORY_BYTES)?,
    })
}

/// The problem of a result: `--problem` (read as it is: an error names it), else the
/// summary's `problem_file`, else (where that is not found or cannot be read, said on stderr)
/// the copy the result carries; with the summary's `parameters` as `--set` overrides.
fn problem_of(result: &Result_, problem: Option<&Path>) -> Result<LoadedProblem, CliError> {
    let mut set = Vec::new();
    if let Some(parameters) = result.summary["parameters"].as_object() {
        for (path, value) in parameters {
            let value = toml::Value::try_from(value)
                .map_err(|e| CliError::Input(format!("summary.json parameter `{path}`: {e}")))?;
            set.push(format!("{path}={value}"));
        }
    }
    if let Some(file) = problem {
        return Ok(load(file, &parse_overrides(&set)?)?);
    }
    let named = result.summary["problem_file"].as_str().ok_or_else(|| {
        CliError::Input(format!(
            "{}: no `problem_file`; name the problem with --problem",
            result.dir.join("summary.json").display()
        ))
    })?;
    let file = PathBuf::from(named);
    // Its type from its metadata: a FIFO or device is never opened.
    let why = match vito::files::input::read_regular_head(&file, 0) {
        Ok(_) => return Ok(load(&file, &parse_overrides(&set)?)?),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => "is not found from here".to_owned(),
        Err(e) => format!("cannot be read ({e})"),
    };
    // The copies the result carries, the URDF named by its copy and a warm start (read when
    // the problem loads) by the result's own trajectory, both relative to the copy (so that
    // no name passes through text: any file name of the result's path stays as it is).
    let copy = &result.summary["problem_copy"];
    let (Some(copy_file), Some(copy_urdf)) = (copy["file"].as_str(), copy["urdf"].as_str()) else {
        return Err(CliError::Input(format!(
            "{}: the problem file {} {why} and the result carries no copy of it; run from the \
             directory the result was made in, or name it with --problem",
            result.dir.display(),
            file.display()
        )));
    };
    let inside = |relative: &str| -> Result<usize, CliError> {
        let components = Path::new(relative).components();
        if components
            .clone()
            .all(|c| matches!(c, std::path::Component::Normal(_)))
        {
            Ok(components.count())
        } else {
            Err(CliError::Input(format!(
                "{}: `problem_copy` names {relative}, outside the result folder",
                result.dir.join("summary.json").display()
            )))
        }
    };
    inside(copy_urdf)?;
    // From the copy's directory up to the result folder.
    let up = "../".repeat(inside(copy_file)?.saturating_sub(1));
    let copy_file = result.dir.join(copy_file);
    let quoted = |relative: &str| toml::Value::String(format!("{up}{relative}"));
    let warm_override = set
        .iter()
        .any(|s| s.starts_with("initial_guess.warm_start="));
    set.retain(|s| !s.starts_with("robot.urdf=") && !s.starts_with("initial_guess.warm_start="));
    set.push(format!("robot.urdf={}", quoted(copy_urdf)));
    let warm_in_file =
        vito::files::input::read_regular_text(&copy_file, vito::files::input::MAX_TEXT_BYTES)
            .ok()
            .and_then(|text| text.parse::<toml::Table>().ok())
            .is_some_and(|t| {
                t.get("initial_guess")
                    .and_then(|g| g.get("warm_start"))
                    .is_some()
            });
    if warm_override || warm_in_file {
        set.push(format!(
            "initial_guess.warm_start={}",
            quoted("trajectory.csv")
        ));
    }
    note!(
        "{}: the problem file {} {why}; drawn from the copy in {}",
        result.dir.display(),
        file.display(),
        copy_file.display()
    );
    Ok(load(&copy_file, &parse_overrides(&set)?)?)
}

/// The motion of a result, its columns read by the problem's names.
fn motion_of(result: &Result_, problem: &LoadedProblem) -> Result<vito::view::Motion, CliError> {
    let bad = |m: String| {
        CliError::Input(format!(
            "{}: {m}",
            result.dir.join("trajectory.csv").display()
        ))
    };
    let recorded =
        vito::files::trajectory_csv::read_trajectory(&result.csv, &problem.robot.coordinates, &[])
            .map_err(bad)?;
    let table = vito::files::trajectory_csv::read_csv(&result.csv).map_err(bad)?;
    let intervals = recorded.times.len() - 1;
    let column = |name: &str| table.column(name).map(|c| c[..intervals].to_vec());
    let contacts: Vec<&str> = problem
        .spec
        .contacts
        .iter()
        .map(|c| c.name.as_str())
        .collect();
    // The problem's own friction basis names the columns ([+x, −x] or [+x, +y, −x, −y]).
    let directions = vito::files::trajectory_csv::friction_direction_names(
        vito::contact::FrictionBasis::for_robot(problem.robot.moves_in_xz_plane).num_directions(),
    );
    let mut normal = vec![Vec::new(); intervals];
    let mut friction = vec![Vec::new(); intervals];
    for c in &contacts {
        let n = column(&format!("{c}_normal")).unwrap_or_else(|| vec![0.0; intervals]);
        let betas: Vec<Vec<f64>> = directions
            .iter()
            .map(|d| column(&format!("{c}_friction_{d}")).unwrap_or_else(|| vec![0.0; intervals]))
            .collect();
        for k in 0..intervals {
            let finite = |v: f64| if v.is_finite() { v } else { 0.0 };
            normal[k].push(finite(n[k]));
            friction[k].push(betas.iter().map(|b| finite(b[k])).collect());
        }
    }
    let legend = vito::view::legend_of(&result.summary);
    Ok(vito::view::Motion {
        name: result.dir.display().to_string(),
        detail: legend.detail,
        standing: legend.standing,
        times: recorded.times,
        q: recorded.q,
        normal,
        friction,
    })
}

/// Refuses to write `path` unless it is new or a regular file vito wrote (`ours` tells from
/// its first bytes), and unless its directory exists; `option` names it in messages. Never
/// blocks: a FIFO or device there is refused from its metadata.
fn replaceable(path: &Path, option: &str, ours: fn(&[u8]) -> bool) -> Result<(), CliError> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(CliError::Input(format!(
            "{option} {}: the directory {} does not exist; create it first or choose another file",
            path.display(),
            dir.display()
        )));
    }
    if std::fs::symlink_metadata(path).is_err() {
        return Ok(());
    }
    let head = vito::files::input::read_regular_head(path, vito::view::MARK_WINDOW as u64)
        .map_err(|e| {
            CliError::Input(format!(
                "{option} {}: {e}; choose another file",
                path.display()
            ))
        })?;
    if ours(&head) {
        Ok(())
    } else {
        Err(CliError::Input(format!(
            "{option} {}: the file exists and vito did not write it; choose another file",
            path.display()
        )))
    }
}

pub(super) fn view(
    dirs: &[PathBuf],
    problem: Option<&Path>,
    out: Option<&Path>,
    strip: Option<usize>,
    svg: Option<&Path>,
    layout: vito::view::StripLayout,
) -> Result<u8, CliError> {
    // Checked before anything is read or drawn.
    if let Some(n) = strip.filter(|&n| n == 0 || n > MAX_STRIP_POSES) {
        return Err(CliError::Input(format!(
            "--strip {n}: give 1 to {MAX_STRIP_POSES} poses"
        )));
    }
    if let Some(svg) = svg {
        if let [_, others @ ..] = dirs
            && !others.is_empty()
        {
            let others: Vec<String> = others.iter().map(|d| d.display().to_string()).collect();
            return Err(CliError::Input(format!(
                "--svg {}: a strip draws one result, and {} would not be in it; give one \
                 directory per strip (several are overlaid on a page with --out alone)",
                svg.display(),
                vito::files::names::list_names(&others, 8)
            )));
        }
        replaceable(svg, "--svg", vito::view::is_vito_strip)?;
    }
    if let Some(out) = out {
        replaceable(out, "--out", vito::view::is_vito_page)?;
    }
    let results: Vec<Result_> = dirs
        .iter()
        .map(|d| read_result(d))
        .collect::<Result<_, _>>()?;
    let first = results
        .first()
        .ok_or_else(|| CliError::Input("give a result directory".into()))?;
    let loaded = problem_of(first, problem)?;
    print_model_warnings(&loaded.robot, !loaded.spec.contacts.is_empty());
    let mut motions = Vec::new();
    for (i, result) in results.iter().enumerate() {
        // Each result with its own problem (overrides differ between sweep runs), drawn with
        // the first's robot: the coordinates must agree.
        let own = if i == 0 {
            loaded.clone()
        } else {
            problem_of(result, problem)?
        };
        if own.robot.coordinates != loaded.robot.coordinates {
            return Err(CliError::Input(format!(
                "{} has another robot than {} ({} against {} coordinates); overlay results of one robot",
                result.dir.display(),
                first.dir.display(),
                own.robot.coordinates.len(),
                loaded.robot.coordinates.len()
            )));
        }
        motions.push(motion_of(result, &own)?);
    }
    let scene = vito::view::scene(&loaded).map_err(|e| CliError::Input(e.to_string()))?;
    let start = std::time::Instant::now();
    let drawing = vito::view::drawing(&scene, &motions);
    vito::view::check_drawable(&scene, &motions, &drawing).map_err(|(motion, e)| {
        let file = match motion {
            Some(i) => results[i].dir.join("trajectory.csv"),
            None => loaded.file.clone(),
        };
        CliError::Input(format!(
            "{}: {e}; nothing was drawn (vito view draws values within these ranges)",
            file.display()
        ))
    })?;
    for w in &drawing.body.warnings {
        note!(
            "{}",
            vito::files::names::escape_controls(&format!("warning: {w}"))
        );
    }
    // A full disk or a file too large: unwritable output (exit 4), as for every command's
    // results; another refusal (no permission, a missing directory) is the user's path.
    let write_err = |e: vito::view::ViewError| {
        let full = matches!(&e, vito::view::ViewError::Io { source, .. }
            if super::error::io_exit_code(source) == super::error::EXIT_OUTPUT);
        let text = match e {
            // The operating system's words, without the temporary file's name.
            vito::view::ViewError::Io { path, source } => {
                use std::io::ErrorKind::{
                    FileTooLarge, PermissionDenied, QuotaExceeded, ReadOnlyFilesystem, StorageFull,
                };
                let source = match (source.raw_os_error(), source.kind()) {
                    (Some(code), _) => std::io::Error::from_raw_os_error(code),
                    (
                        None,
                        kind @ (StorageFull | FileTooLarge | QuotaExceeded | ReadOnlyFilesystem
                        | PermissionDenied),
                    ) => kind.into(),
                    _ => source,
                };
                format!("{}: {source}", path.display())
            }
            other => other.to_string(),
        };
        let message = format!(
            "cannot write {text}; nothing there was replaced: free some space or choose another file"
        );
        if full {
            CliError::Output(message)
        } else {
            CliError::Input(message)
        }
    };
    if let (Some(n), Some(svg)) = (strip, svg) {
        vito::view::write_atomically(
            svg,
            &vito::view::strip_svg(&scene, &drawing, &motions[0], n, layout),
        )
        .map_err(write_err)?;
        let frame = match layout {
            vito::view::StripLayout::Panels => "",
            vito::view::StripLayout::World => ", one world frame",
        };
        out!("strip        {} ({n} poses{frame})", svg.display());
    }
    if out.is_some() || svg.is_none() {
        let path = match out {
            Some(p) => p.to_owned(),
            None if results.len() == 1 => first.dir.join("animation.html"),
            None => {
                return Err(CliError::Input(
                    "several directories: name the overlay's file with --out".into(),
                ));
            }
        };
        replaceable(
            &path,
            if out.is_some() { "--out" } else { "page" },
            vito::view::is_vito_page,
        )?;
        let html = vito::view::page(&scene, &motions, &drawing);
        vito::view::write_atomically(&path, &html).map_err(write_err)?;
        out!(
            "animation    {} ({} motion(s), {:.0} kB, {:.3} s)",
            path.display(),
            motions.len(),
            html.len() as f64 / 1e3,
            start.elapsed().as_secs_f64()
        );
    }
    Ok(0)
}
