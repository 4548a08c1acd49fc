//! The temporary files and directories being written, and what becomes of
//! them when the process is interrupted.
//!
//! Every temporary an [`crate::AtomicFile`] or [`crate::atomic::write_tree`]
//! stages is registered here while it exists. The first registration
//! installs a handler for `SIGINT`, `SIGTERM` and `SIGHUP` (crate
//! `signal-hook`: the signal is taken by a thread of its own, outside the
//! restricted context of a signal handler): on such a signal the thread
//! removes every registered temporary, then ends the process by the same
//! signal's default action, so that the shell sees the interruption it
//! asked for (exit status 130 for `SIGINT`).
//!
//! Creating, committing (the rename into place) and discarding a temporary
//! happen under the registry's lock, which the thread takes before it
//! removes anything and never gives back: an interruption either comes
//! before a rename, and the destination keeps its old contents, or after
//! it, and the destination is whole. `SIGKILL` cannot be caught: a killed
//! writer may leave its temporary `.NAME.XXXXXX` behind (never a partial
//! destination).

use std::path::PathBuf;
use std::sync::{Mutex, MutexGuard, OnceLock};

/// A registered temporary: what to remove on an interruption.
#[derive(Debug)]
enum Entry {
    File(PathBuf),
    Dir(PathBuf),
}

/// The temporaries that exist, by the number [`register`] gave them.
static LIVE: Mutex<Vec<(u64, Entry)>> = Mutex::new(Vec::new());

/// The registry, even after a panic elsewhere while it was held.
fn live() -> MutexGuard<'static, Vec<(u64, Entry)>> {
    LIVE.lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Runs `create` under the registry's lock and registers the temporary
/// file (`dir: false`) or directory (`dir: true`) at the path it returns
/// with its value; returns the value and the registration's number, for
/// [`locked`].
pub(crate) fn register<T>(
    dir: bool,
    create: impl FnOnce() -> std::io::Result<(T, PathBuf)>,
) -> std::io::Result<(T, u64)> {
    install_handler();
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let mut live = live();
    let (value, path) = create()?;
    let number = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    live.push((
        number,
        if dir {
            Entry::Dir(path)
        } else {
            Entry::File(path)
        },
    ));
    Ok((value, number))
}

/// Runs `finish` (a rename into place, or the removal of a temporary)
/// under the registry's lock, then forgets registration `number`.
pub(crate) fn locked<T>(number: u64, finish: impl FnOnce() -> T) -> T {
    let mut live = live();
    let result = finish();
    live.retain(|(n, _)| *n != number);
    result
}

/// Removes every registered temporary; the lock stays taken, so that no
/// temporary is created or renamed after.
fn remove_all() -> MutexGuard<'static, Vec<(u64, Entry)>> {
    let live = live();
    for (_, entry) in live.iter() {
        // Nothing to report to: the process is ending.
        let _ = match entry {
            Entry::File(path) => std::fs::remove_file(path),
            Entry::Dir(path) => std::fs::remove_dir_all(path),
        };
    }
    live
}

/// Installs the interruption handler, once (see the module documentation).
/// Where it cannot be installed the writes stay atomic; only the cleanup
/// on an interruption is lost.
fn install_handler() {
    static INSTALLED: OnceLock<()> = OnceLock::new();
    INSTALLED.get_or_init(|| {
        #[cfg(unix)]
        {
            use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
            let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])
            else {
                return;
            };
            let _ = std::thread::Builder::new()
                .name("slamjac-io interruption".into())
                .spawn(move || {
                    if let Some(signal) = signals.forever().next() {
                        let _held = remove_all();
                        // Resets the default action and raises the signal:
                        // the process ends as if never caught (it aborts
                        // where that fails).
                        let _ = signal_hook::low_level::emulate_default_handler(signal);
                        std::process::abort();
                    }
                });
        }
    });
}
