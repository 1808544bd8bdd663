//! Where Spreadlight keeps its own files on a machine: one place that knows
//! the directories, so the renderer's pipeline cache and the editor's
//! settings follow the same rules. Each is its `SPREADLIGHT_*` variable if
//! set (tests and farm workers point it elsewhere), else the XDG base
//! directory's `spreadlight` folder, else the same under `$HOME`, else the
//! temporary directory.

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
}

const CACHE: AppDir = AppDir {
    own: "SPREADLIGHT_CACHE_DIR",
    xdg: "XDG_CACHE_HOME",
    home: ".cache",
    temp: "spreadlight-cache",
};

const CONFIG: AppDir = AppDir {
    own: "SPREADLIGHT_CONFIG_DIR",
    xdg: "XDG_CONFIG_HOME",
    home: ".config",
    temp: "spreadlight",
};

impl AppDir {
    /// The directory, reading the environment through `var`.
    fn find(&self, var: impl Fn(&str) -> Option<OsString>) -> PathBuf {
        if let Some(dir) = var(self.own) {
            return PathBuf::from(dir);
        }
        if let Some(dir) = var(self.xdg) {
            return PathBuf::from(dir).join("spreadlight");
        }
        match var("HOME") {
            Some(home) => PathBuf::from(home).join(self.home).join("spreadlight"),
            None => std::env::temp_dir().join(self.temp),
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
}
