//! Long library calls run from Python: the work (a solve, a simulation, a sweep) runs on its
//! own thread, which never touches Python, while the calling thread waits without the GIL
//! and takes it only briefly to pass on the work's messages (a `progress` callable) and to
//! check for signals (Ctrl-C), at least every [`POLL`]. The first Python exception asks the
//! work to stop (its flag) and is returned once the work has ended.
//!
//! So no thread holds the GIL while waiting for vito's own locks (the one-solve-at-a-time
//! Ipopt lock is taken on the work's thread), and no thread holds such a lock across a call
//! into Python: a message the work waits for (a progress callback, so that an exception or a
//! Ctrl-C in it stops the solve at that iteration) is waited for only while no other thread
//! waits for the Ipopt lock, since that thread may be the one the callback waits for.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender, channel};
use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::time::Duration;

use pyo3::prelude::*;

/// How often the waiting thread checks for signals.
pub(crate) const POLL: Duration = Duration::from_millis(50);

/// The waiting thread's word that it has handled a message.
#[derive(Default)]
pub(crate) struct Ack {
    done: Mutex<bool>,
    changed: Condvar,
}

impl Ack {
    fn set(&self) {
        *self.done.lock().unwrap_or_else(PoisonError::into_inner) = true;
        self.changed.notify_all();
    }

    /// Waits until the message is handled, or until another thread waits for the Ipopt lock
    /// this thread may hold.
    fn wait(&self) {
        let mut done = self.done.lock().unwrap_or_else(PoisonError::into_inner);
        while !*done && !vito::ipopt::others_waiting_for_ipopt() {
            done = self
                .changed
                .wait_timeout(done, Duration::from_millis(5))
                .unwrap_or_else(PoisonError::into_inner)
                .0;
        }
    }
}

/// A message and, when the work waits for it to be handled, the handler's word.
type Message<M> = (M, Option<Arc<Ack>>);

/// The work's end of the channel.
pub(crate) struct Messages<M> {
    tx: Sender<Message<M>>,
}

impl<M> Messages<M> {
    /// Sends a message and goes on.
    pub(crate) fn send(&self, message: M) {
        let _ = self.tx.send((message, None));
    }

    /// Sends a message and waits until the caller has handled it (see the module's rule).
    pub(crate) fn send_and_wait(&self, message: M) {
        let ack = Arc::new(Ack::default());
        if self.tx.send((message, Some(ack.clone()))).is_ok() {
            ack.wait();
        }
    }
}

/// Runs `work` on its own thread; `on_message` handles its messages on this thread with the
/// GIL. Returns the work's result and the first Python exception (a signal's, or one raised
/// by `on_message`), after which `stop` was set and no further message was handled.
pub(crate) fn run_watched<T: Send, M: Send>(
    py: Python<'_>,
    stop: &Arc<AtomicBool>,
    work: impl FnOnce(Messages<M>) -> T + Send,
    mut on_message: impl FnMut(Python<'_>, M) -> PyResult<()> + Send,
) -> (T, Option<PyErr>) {
    let (tx, rx): (Sender<Message<M>>, Receiver<Message<M>>) = channel();
    py.detach(move || {
        let mut error: Option<PyErr> = None;
        let result = std::thread::scope(|s| {
            let worker = s.spawn(move || work(Messages { tx }));
            loop {
                let received = rx.recv_timeout(POLL);
                let (message, ack) = match received {
                    Ok((m, ack)) => (Some(m), ack),
                    Err(RecvTimeoutError::Timeout) => (None, None),
                    Err(RecvTimeoutError::Disconnected) => break,
                };
                if error.is_none() {
                    let outcome = Python::attach(|py| {
                        py.check_signals()?;
                        match message {
                            Some(m) => on_message(py, m),
                            None => Ok(()),
                        }
                    });
                    if let Err(e) = outcome {
                        stop.store(true, Ordering::SeqCst);
                        error = Some(e);
                    }
                }
                if let Some(ack) = ack {
                    ack.set();
                }
            }
            match worker.join() {
                Ok(result) => result,
                Err(panic) => std::panic::resume_unwind(panic),
            }
        });
        (result, error)
    })
}
