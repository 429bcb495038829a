//! Stop requests: SIGINT (Ctrl-C), SIGTERM (`scancel`, a Slurm time limit, `kill`) and
//! SIGHUP all ask the command to stop cleanly. Signals arriving within [`SAME_REQUEST`] of
//! the first count as that one request (`timeout -s INT` and a terminal's Ctrl-C send to
//! the process and its group at once); one arriving later asks to quit at once.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

/// Signals this close together are one stop request.
pub(super) const SAME_REQUEST: Duration = Duration::from_secs(1);

/// Installs the process's stop handler: the first request sets the returned flag and calls
/// `on_stop`; a later one (after [`SAME_REQUEST`]) calls `on_quit`, which should exit.
/// Signals within [`SAME_REQUEST`] of the first are ignored.
pub(super) fn on_stop_request(
    on_stop: impl Fn() + Send + 'static,
    on_quit: impl Fn() + Send + 'static,
) -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let set = flag.clone();
    let mut first: Option<Instant> = None;
    // A second handler cannot be installed in one process; ignoring that error keeps the
    // first (which sets the same kind of flag) in place.
    let _ = ctrlc::set_handler(move || match first {
        None => {
            first = Some(Instant::now());
            set.store(true, std::sync::atomic::Ordering::SeqCst);
            on_stop();
        }
        Some(t) if t.elapsed() < SAME_REQUEST => {}
        Some(_) => on_quit(),
    });
    flag
}
