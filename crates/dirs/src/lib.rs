//! Where Spreadlight keeps its own files on a machine: one place that knows
//! the directories, so the renderer's pipeline cache, the editor's settings
//! and the patch runtime's subpatch library follow the same rules. Each is its
//! `SPREADLIGHT_*` variable if set (tests and farm workers point it
//! elsewhere), else the XDG base directory's `spreadlight` folder, else the
//! same under `$HOME`, else the temporary directory.
//!
//! A crate of its own because the renderer (no patch) and the patch runtime
//! (no GPU) both need it and neither may depend on the other.

use std::ffi::OsString;
use std::path::PathBuf;

/// The pipeline cache's directory (`crate::pipeline_cache`):
/// `SPREADLIGHT_CACHE_DIR`, else `$XDG_CACHE_HOME/spreadlight`, else
/// `~/.cache/spreadlight`.
pub fn cache_dir() -> PathBuf {
    CACHE.find(|name| std::env::var_os(name))
}

/// The editor's settings, recent files and autosaves: `SPREADLIGHT_CONFIG_DIR`,
/// else `$XDG_CONFIG_HOME/spreadlight`, else `~/.config/spreadlight`.
pub fn config_dir() -> PathBuf {
    CONFIG.find(|name| std::env::var_os(name))
}

/// The user's subpatch library (`graph::subpatch`): `SPREADLIGHT_LIBRARY`,
/// else `$XDG_DATA_HOME/spreadlight/library`, else
/// `~/.local/share/spreadlight/library`.
pub fn library_dir() -> PathBuf {
    LIBRARY.find(|name| std::env::var_os(name))
}

/// The variable naming the user's subpatch library folder.
pub const LIBRARY_ENV: &str = "SPREADLIGHT_LIBRARY";

/// One of the app's directories, by the variables and folders that name it.
struct AppDir {
    /// Spreadlight's own variable: the directory itself.
    own: &'static str,
    /// The XDG base directory variable it sits in.
    xdg: &'static str,
    /// The base directory's usual place under `$HOME`.
    home: &'static str,
    /// Its name in the temporary directory, with no `$HOME` either.
    temp: &'static str,
    /// A folder inside the base directory's `spreadlight` folder, if the
    /// directory is not that folder itself.
    inside: Option<&'static str>,
}

const CACHE: AppDir = AppDir {
    own: "SPREADLIGHT_CACHE_DIR",
    xdg: "XDG_CACHE_HOME",
    home: ".cache",
    temp: "spreadlight-cache",
    inside: None,
};

const CONFIG: AppDir = AppDir {
    own: "SPREADLIGHT_CONFIG_DIR",
    xdg: "XDG_CONFIG_HOME",
    home: ".config",
    temp: "spreadlight",
    inside: None,
};

/// The library is a folder inside the data directory, not the directory
/// itself: the data directory may hold other things one day.
const LIBRARY: AppDir = AppDir {
    own: LIBRARY_ENV,
    xdg: "XDG_DATA_HOME",
    home: ".local/share",
    temp: "spreadlight-library",
    inside: Some("library"),
};

impl AppDir {
    /// The directory, reading the environment through `var`.
    fn find(&self, var: impl Fn(&str) -> Option<OsString>) -> PathBuf {
        if let Some(dir) = var(self.own) {
            return PathBuf::from(dir);
        }
        let base = match (var(self.xdg), var("HOME")) {
            (Some(xdg), _) => PathBuf::from(xdg),
            (None, Some(home)) => PathBuf::from(home).join(self.home),
            (None, None) => return std::env::temp_dir().join(self.temp),
        };
        let ours = base.join("spreadlight");
        match self.inside {
            Some(folder) => ours.join(folder),
            None => ours,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The directory `dir` names in an environment of `vars` alone.
    fn with(dir: &AppDir, vars: &[(&str, &str)]) -> PathBuf {
        dir.find(|name| {
            vars.iter()
                .find(|(n, _)| *n == name)
                .map(|(_, v)| OsString::from(v))
        })
    }

    #[test]
    fn each_directory_is_its_variable_else_xdg_else_home_else_temp() {
        let all = [
            ("SPREADLIGHT_CACHE_DIR", "/own/cache"),
            ("SPREADLIGHT_CONFIG_DIR", "/own/config"),
            ("XDG_CACHE_HOME", "/xdg/cache"),
            ("XDG_CONFIG_HOME", "/xdg/config"),
            ("HOME", "/home/u"),
        ];
        assert_eq!(with(&CACHE, &all), PathBuf::from("/own/cache"));
        assert_eq!(with(&CONFIG, &all), PathBuf::from("/own/config"));
        assert_eq!(
            with(&CACHE, &all[2..]),
            PathBuf::from("/xdg/cache/spreadlight")
        );
        assert_eq!(
            with(&CONFIG, &all[2..]),
            PathBuf::from("/xdg/config/spreadlight")
        );
        let home = &all[4..];
        assert_eq!(
            with(&CACHE, home),
            PathBuf::from("/home/u/.cache/spreadlight")
        );
        assert_eq!(
            with(&CONFIG, home),
            PathBuf::from("/home/u/.config/spreadlight")
        );
        let temp = std::env::temp_dir();
        assert_eq!(with(&CACHE, &[]), temp.join("spreadlight-cache"));
        assert_eq!(with(&CONFIG, &[]), temp.join("spreadlight"));
    }

    #[test]
    fn the_subpatch_library_is_a_folder_in_the_data_directory() {
        let all = [
            ("SPREADLIGHT_LIBRARY", "/own/library"),
            ("XDG_DATA_HOME", "/xdg/data"),
            ("HOME", "/home/u"),
        ];
        assert_eq!(with(&LIBRARY, &all), PathBuf::from("/own/library"));
        assert_eq!(
            with(&LIBRARY, &all[1..]),
            PathBuf::from("/xdg/data/spreadlight/library")
        );
        assert_eq!(
            with(&LIBRARY, &all[2..]),
            PathBuf::from("/home/u/.local/share/spreadlight/library")
        );
        assert_eq!(
            with(&LIBRARY, &[]),
            std::env::temp_dir().join("spreadlight-library")
        );
    }
}
