//! A dependency's panic kept from the user: [`guarded`] runs a call into a crate that can
//! still panic on valid-looking input (mesh-loader's COLLADA reader indexes its vertices with
//! the file's indices; parry's convex hull unwraps on inputs it finds degenerate) and turns a
//! panic into an error message. Inputs are checked before such calls (`limits.rs`,
//! `numbers.rs`, the hull's degeneracy in `shapes.rs`); this is the last line behind them.
//! The panic's default message ("thread 'main' panicked at ...") is not printed for a panic
//! caught here: a process-wide hook, installed once, stays silent while the current thread is
//! inside [`guarded`] and calls the previous hook otherwise.

use std::cell::Cell;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Once;

thread_local! {
    /// True while this thread runs a guarded call.
    static GUARDED: Cell<bool> = const { Cell::new(false) };
}

static HOOK: Once = Once::new();

/// Runs `f`; a panic inside it becomes `Err(message)` (`what`: the call, for the message).
pub(crate) fn guarded<T>(what: &str, f: impl FnOnce() -> T) -> Result<T, String> {
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !GUARDED.with(Cell::get) {
                previous(info);
            }
        }));
    });
    let outer = GUARDED.with(|g| g.replace(true));
    // AssertUnwindSafe: nothing `f` borrows is used after a panic (the error is returned and
    // the caller's partial state dropped).
    let r = catch_unwind(AssertUnwindSafe(f));
    GUARDED.with(|g| g.set(outer));
    r.map_err(|p| {
        let why = p
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| p.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        format!(
            "{what} failed inside a dependency ({}); the file is malformed",
            crate::check::shorten(&why)
        )
    })
}
