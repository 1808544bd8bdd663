//! Frame files on disk. Every file is written to a temporary name beside
//! its target (`.NAME.HOST-PID.partial`), synced and renamed over it, so a
//! killed run leaves whole frames or none; a frame counts as complete only
//! when it is whole at the expected size (`whole.rs`); and the partial files of runs that
//! were killed on this host are swept before a run renders the same frames.

use std::collections::HashSet;
use std::ffi::OsString;
use std::io::Write;
use std::path::{Path, PathBuf};

const PARTIAL: &str = ".partial";

/// This machine's name, as partial files record it (a farm shares one folder).
fn host() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_owned())
        .ok()
        .filter(|h| !h.is_empty() && !h.contains(['/', '.']))
        .unwrap_or_else(|| "localhost".to_owned())
}

/// Where `path` is written before it is renamed into place.
pub fn partial_path(path: &Path) -> PathBuf {
    let file = path
        .file_name()
        .map(|f| f.to_string_lossy())
        .unwrap_or_default();
    path.with_file_name(format!(
        ".{file}.{}-{}{PARTIAL}",
        host(),
        std::process::id()
    ))
}

/// The first half of an atomic write: `bytes` in `path`'s temporary file;
/// returns its name and the file, to be synced (`File::sync_all`) before
/// the rename. A sequence writes frames this way on several threads, syncs
/// them on others and [`commit`]s them in frame order, so the frames on
/// disk are always the first ones of the run (what resuming relies on).
pub fn create_partial(path: &Path, bytes: &[u8]) -> std::io::Result<(PathBuf, std::fs::File)> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    let partial = partial_path(path);
    let result = (|| {
        let mut file = std::fs::File::create(&partial)?;
        file.write_all(bytes)?;
        Ok(file)
    })();
    match result {
        Ok(file) => Ok((partial, file)),
        Err(e) => {
            let _ = std::fs::remove_file(&partial);
            Err(e)
        }
    }
}

/// The second half of an atomic write: rename `partial` over `path` (or,
/// failing that, remove it).
pub fn commit(partial: &Path, path: &Path) -> std::io::Result<()> {
    let result = std::fs::rename(partial, path);
    if result.is_err() {
        let _ = std::fs::remove_file(partial);
    }
    result
}

/// Whether `path` holds a whole image of `size` (a file cut short, or of
/// another size, is redone).
pub fn is_complete(path: &Path, size: (u32, u32)) -> bool {
    super::whole::is_whole(path, size)
}

/// Remove the partial files of `targets` that a process of this host left
/// behind when it was killed (its id no longer runs). Another host's, or a
/// live process's, are left alone. Returns how many were removed.
pub fn sweep_partials(targets: &[PathBuf]) -> usize {
    let mut by_dir: std::collections::BTreeMap<PathBuf, HashSet<OsString>> = Default::default();
    for path in targets {
        let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
        if let Some(file) = path.file_name() {
            by_dir.entry(dir).or_default().insert(file.to_owned());
        }
    }
    let host = host();
    let mut removed = 0;
    for (dir, files) in by_dir {
        let listing = if dir.as_os_str().is_empty() {
            std::fs::read_dir(".")
        } else {
            std::fs::read_dir(&dir)
        };
        let Ok(listing) = listing else { continue };
        for entry in listing.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            let Some((file, owner_host, pid)) = parse_partial(&name) else {
                continue;
            };
            let dead = owner_host == host && !process_runs(pid);
            if dead
                && files.contains(&OsString::from(file))
                && std::fs::remove_file(entry.path()).is_ok()
            {
                removed += 1;
            }
        }
    }
    removed
}

/// Whether process `pid` of this host still runs. A killed process whose
/// parent is gone stays a zombie until something reaps it, and in a container
/// whose first process reaps nothing that is for ever: its `/proc` entry is
/// there, its state `Z` (or `X`). A farm worker's renderer, killed with its
/// worker mid-write, is such a process (tools/farm: `PR_SET_PDEATHSIG`).
fn process_runs(pid: u32) -> bool {
    let Ok(stat) = std::fs::read_to_string(format!("/proc/{pid}/stat")) else {
        return false;
    };
    // `PID (COMMAND) STATE ...`: the command may hold spaces and parentheses.
    let state = stat
        .rfind(')')
        .and_then(|end| stat[end + 1..].split_whitespace().next());
    !matches!(state, Some("Z" | "X") | None)
}

/// `.FILE.HOST-PID.partial` -> (FILE, HOST, PID).
fn parse_partial(name: &str) -> Option<(&str, &str, u32)> {
    let inner = name.strip_prefix('.')?.strip_suffix(PARTIAL)?;
    let (rest, pid) = inner.rsplit_once('-')?;
    let (file, host) = rest.rsplit_once('.')?;
    Some((file, host, pid.parse().ok()?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_zombie_writer_is_dead_and_a_running_one_is_not() {
        assert!(process_runs(std::process::id()));
        assert!(!process_runs(u32::MAX), "no such process");
        // A child that exited and was not waited for is a zombie until it is.
        let mut child = std::process::Command::new("true").spawn().expect("spawn");
        let pid = child.id();
        let zombie = (0..500).any(|_| {
            std::thread::sleep(std::time::Duration::from_millis(10));
            !process_runs(pid)
        });
        assert!(
            Path::new(&format!("/proc/{pid}")).exists(),
            "still listed until it is reaped"
        );
        assert!(zombie, "an exited, unreaped child counts as dead");
        child.wait().expect("reap");
    }

    #[test]
    fn partial_names_round_trip() {
        let p = partial_path(Path::new("out/shot_0001.exr"));
        let name = p.file_name().expect("name").to_string_lossy().into_owned();
        let (file, h, pid) = parse_partial(&name).expect("parses");
        assert_eq!(
            (file, h, pid),
            ("shot_0001.exr", host().as_str(), std::process::id())
        );
        assert_eq!(p.parent(), Some(Path::new("out")));
    }

    #[test]
    fn atomic_writes_leave_only_the_file_and_sweeps_spare_live_writers() {
        let dir = tempfile::tempdir().expect("tempdir");
        let target = dir.path().join("a/shot_0001.png");
        let (partial, file) = create_partial(&target, b"whole").expect("write");
        file.sync_all().expect("sync");
        assert_eq!(partial, partial_path(&target));
        assert!(!target.exists(), "not in place before the commit");
        commit(&partial, &target).expect("rename");
        assert_eq!(std::fs::read(&target).expect("read"), b"whole");
        let names: Vec<_> = std::fs::read_dir(target.parent().expect("dir"))
            .expect("ls")
            .map(|e| e.expect("entry").file_name())
            .collect();
        assert_eq!(names, [OsString::from("shot_0001.png")]);

        // A dead writer's partial file (pid far beyond pid_max) goes; ours stays.
        let dead = target.with_file_name(format!(".shot_0001.png.{}-4294967295.partial", host()));
        std::fs::write(&dead, b"half").expect("write");
        let live = partial_path(&target);
        std::fs::write(&live, b"half").expect("write");
        assert_eq!(sweep_partials(std::slice::from_ref(&target)), 1);
        assert!(!dead.exists() && live.exists());
        assert!(!is_complete(&target, (1, 1)), "not an image");
    }
}
