//! Output files: their paths (`BASE.exr`, `BASE.TERM.png`), the check that
//! their folder exists before any work is done, and the
//! write-to-a-temporary-then-rename that keeps an existing output whole if
//! anything fails.

use crate::error::{CliError, Result};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// `base` with the extension `ext` appended (`out` → `out.exr`, `a.b` → `a.b.exr`).
pub fn with_ext(base: &Path, ext: &str) -> PathBuf {
    let mut s = base.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// Checks that `path`'s folder exists and `path` is not a folder, naming
/// the option `field` otherwise.
pub fn check_output(field: &str, path: &Path) -> Result<()> {
    let dir = parent(path);
    if !dir.is_dir() {
        return Err(CliError::Input(format!(
            "{field} = {}: the folder {} does not exist; allowed: a path in an existing folder",
            path.display(),
            dir.display()
        )));
    }
    if path.is_dir() {
        return Err(CliError::Input(format!(
            "{field} = {} is a folder; allowed: a file path",
            path.display()
        )));
    }
    Ok(())
}

/// The folder of `path` (`.` for a bare file name).
fn parent(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Writes `path` through a temporary file in the same folder (`tempfile`),
/// renamed over `path` only once `write` has succeeded and the data is
/// flushed and synced: an existing `path` is either left as it was or
/// replaced whole, and a failed write leaves no temporary file behind.
///
/// The file gets the mode a newly created file gets from the user's umask
/// (`0o666 & !umask`, as `File::create` gives), not the temporary file's
/// private `0o600`.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> Result<()> {
    let io = |e: std::io::Error| CliError::Io(format!("cannot write {}: {e}", path.display()));
    let mut builder = tempfile::Builder::new();
    builder.prefix(".omnee-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // The kernel applies the umask to the mode given to open(2).
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let tmp = builder.tempfile_in(parent(path)).map_err(io)?;
    let (file, tmp_path) = tmp.into_parts();
    let mut w = BufWriter::new(file);
    write(&mut w).map_err(io)?;
    w.flush().map_err(io)?;
    w.get_ref().sync_all().map_err(io)?;
    drop(w);
    tmp_path.persist(path).map_err(|e| io(e.error))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_the_old_file_whole() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("keep.png");
        std::fs::write(&path, b"old").unwrap();
        let r = write_atomic(&path, |w| {
            w.write_all(b"half")?;
            Err(std::io::Error::other("disk full"))
        });
        assert!(r.is_err());
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn extensions_are_appended() {
        assert_eq!(with_ext(Path::new("a.b"), "exr"), PathBuf::from("a.b.exr"));
        assert_eq!(
            with_ext(Path::new("dir/out"), "once-more.png"),
            PathBuf::from("dir/out.once-more.png")
        );
    }
}
