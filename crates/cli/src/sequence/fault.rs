//! A test hook for the sequence writer: `SPREADLIGHT_TEST_KILL_AT` makes a
//! render abort at a chosen point, with no cleanup, as a SIGKILL there
//! would. A test cannot time a real kill into the microseconds between a
//! frame's temporary file and its rename; this puts the abort exactly there
//! (`after-write:N`: frame N's first file written and synced, not yet
//! renamed) or between two frames (`between-frames:N`: frame N's files in
//! place, frame N+1 not started), so `crates/cli/tests/sequence.rs` can
//! resume and compare the files with an uninterrupted run. Nothing else
//! reads the variable; unset, the hook does nothing.

/// The environment variable the hook reads.
pub const VARIABLE: &str = "SPREADLIGHT_TEST_KILL_AT";

/// Where to abort.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum KillAt {
    #[default]
    Never,
    /// After writing frame N's first temporary file, before renaming it.
    AfterWrite(u64),
    /// After frame N's files are in place, before the next frame.
    BetweenFrames(u64),
}

impl KillAt {
    /// The hook the environment asks for; a value it cannot read is an error
    /// (a test that meant to kill must not pass by running to the end).
    pub fn from_env() -> Result<KillAt, String> {
        match std::env::var(VARIABLE) {
            Ok(value) => KillAt::parse(&value),
            Err(std::env::VarError::NotPresent) => Ok(KillAt::Never),
            Err(e) => Err(format!("{VARIABLE}: {e}")),
        }
    }

    fn parse(value: &str) -> Result<KillAt, String> {
        let bad = || {
            format!(
                "{VARIABLE}=`{value}`: write `after-write:FRAME` or `between-frames:FRAME` (or leave it unset)"
            )
        };
        let (point, frame) = value.split_once(':').ok_or_else(bad)?;
        let frame: u64 = frame.trim().parse().map_err(|_| bad())?;
        match point.trim() {
            "after-write" => Ok(KillAt::AfterWrite(frame)),
            "between-frames" => Ok(KillAt::BetweenFrames(frame)),
            _ => Err(bad()),
        }
    }

    /// Frame `frame`'s temporary file is written and synced, not renamed.
    pub fn after_write(self, frame: u64) {
        if self == KillAt::AfterWrite(frame) {
            abort(&format!(
                "after writing frame {frame}'s temporary file, before renaming it"
            ));
        }
    }

    /// Frame `frame` is done; the next has not started.
    pub fn between_frames(self, frame: u64) {
        if self == KillAt::BetweenFrames(frame) {
            abort(&format!("after frame {frame}, before the next"));
        }
    }
}

fn abort(when: &str) -> ! {
    eprintln!("{VARIABLE}: aborting {when}");
    // No destructors, no flushing of our files: what a SIGKILL leaves.
    std::process::abort()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kill_points_parse_and_nonsense_is_refused() {
        assert_eq!(KillAt::parse("after-write:3"), Ok(KillAt::AfterWrite(3)));
        assert_eq!(
            KillAt::parse("between-frames:12"),
            Ok(KillAt::BetweenFrames(12))
        );
        for bad in ["after-write", "after-write:x", "before-write:3", ""] {
            assert!(KillAt::parse(bad).is_err(), "{bad}");
        }
        // Points that do not match never abort (this test would die if they did).
        KillAt::AfterWrite(3).after_write(2);
        KillAt::AfterWrite(3).between_frames(3);
        KillAt::BetweenFrames(3).after_write(3);
        KillAt::Never.between_frames(0);
    }
}
