//! The warning for a file cut off mid-write, printed by every replay (the messages
//! about a path that cannot be read are the lab's: `stridekit_lab::replay::input`).

use std::path::Path;

/// Print the warning for a file cut off mid-write (stderr, always).
pub fn warn_truncated(path: &Path) {
    eprintln!(
        "warning: {} was cut off mid-write (it ends inside a record, or before its \
         end marker): read up to its last complete record; the result covers only that part",
        path.display()
    );
}
