//! How a sequence reports itself: a progress bar (frames done, the last
//! frame's time, ETA) on a terminal; a line per frame on stderr otherwise;
//! JSON lines on stdout with `--json`, for farms and scripts.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{Value, json};

/// What became of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// Rendered and written.
    Written,
    /// Its files were complete already.
    Skipped,
    /// A node or pass failed, or a file could not be written: nothing written for it.
    Failed,
    /// `--dry-run`: it would be rendered.
    Missing,
}

impl Status {
    fn word(self) -> &'static str {
        match self {
            Status::Written => "written",
            Status::Skipped => "skipped",
            Status::Failed => "failed",
            Status::Missing => "missing",
        }
    }
}

pub struct Progress {
    json: bool,
    bar: Option<ProgressBar>,
    started: Instant,
}

impl Progress {
    /// `todo`: frames that will be rendered (the bar's length).
    pub fn new(json: bool, todo: u64) -> Self {
        let bar = (!json && std::io::stderr().is_terminal()).then(|| {
            let bar = ProgressBar::new(todo);
            bar.set_style(
                ProgressStyle::with_template(
                    "{bar:32} {pos}/{len} frames  {msg}  elapsed {elapsed}  ETA {eta}",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            bar.enable_steady_tick(Duration::from_millis(250));
            bar
        });
        Progress {
            json,
            bar,
            started: Instant::now(),
        }
    }

    /// A line for people (above the bar), or nothing with `--json`.
    pub fn note(&self, line: &str) {
        match (&self.bar, self.json) {
            (Some(bar), _) => bar.println(line),
            (None, false) => eprintln!("{line}"),
            (None, true) => {}
        }
    }

    /// An error: on stderr always, and as a JSON line.
    pub fn error(&self, frame: Option<u64>, message: &str) {
        match &self.bar {
            Some(bar) => bar.println(format!("error: {message}")),
            None => eprintln!("error: {message}"),
        }
        if self.json {
            println!(
                "{}",
                json!({"event": "error", "frame": frame, "message": message})
            );
        }
    }

    pub fn start(&self, info: Value) {
        if self.json {
            let mut line = json!({"event": "start"});
            merge(&mut line, info);
            println!("{line}");
        }
    }

    /// `files`: the output name and the path of each file the frame has.
    pub fn frame(&self, frame: u64, status: Status, seconds: f64, files: &[(String, String)]) {
        if self.json {
            let files: serde_json::Map<String, Value> = files
                .iter()
                .map(|(name, path)| (name.clone(), Value::from(path.as_str())))
                .collect();
            println!(
                "{}",
                json!({"event": "frame", "frame": frame, "status": status.word(), "seconds": seconds, "files": files})
            );
        }
        let rendered = matches!(status, Status::Written | Status::Failed);
        match &self.bar {
            Some(bar) if rendered => {
                bar.set_message(format!("frame {frame}: {:.2} s", seconds));
                bar.inc(1);
            }
            Some(_) => {}
            None if !self.json => {
                let what = files
                    .iter()
                    .map(|f| f.1.as_str())
                    .collect::<Vec<_>>()
                    .join(", ");
                match status {
                    Status::Written => eprintln!("frame {frame}: wrote {what} ({seconds:.2} s)"),
                    Status::Skipped => eprintln!("frame {frame}: complete, skipped ({what})"),
                    Status::Failed => eprintln!("frame {frame}: FAILED ({seconds:.2} s)"),
                    Status::Missing => eprintln!("frame {frame}: to render ({what})"),
                }
            }
            None => {}
        }
    }

    /// The summary; returns the seconds since the start.
    pub fn finish(&self, summary: Value) -> f64 {
        let seconds = self.started.elapsed().as_secs_f64();
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
        let mut line = json!({"event": "done", "seconds": seconds});
        merge(&mut line, summary);
        if let Some(written) = line["written"].as_u64().filter(|w| *w > 0) {
            line["fps"] = json!(written as f64 / seconds.max(1e-9));
        }
        if self.json {
            println!("{line}");
        } else {
            eprintln!("{}", human(&line));
        }
        seconds
    }
}

fn merge(into: &mut Value, from: Value) {
    if let (Some(into), Value::Object(from)) = (into.as_object_mut(), from) {
        into.extend(from);
    }
}

fn human(summary: &Value) -> String {
    let n = |k: &str| summary[k].as_u64().unwrap_or(0);
    let mut line = format!(
        "{} written, {} skipped (complete), {} failed in {:.1} s",
        n("written"),
        n("skipped"),
        summary["failed"].as_array().map_or(0, Vec::len),
        summary["seconds"].as_f64().unwrap_or(0.0)
    );
    if let Some(fps) = summary["fps"].as_f64() {
        line.push_str(&format!(" ({fps:.3} frames/s)"));
    }
    if let Some(failed) = summary["failed"].as_array().filter(|f| !f.is_empty()) {
        let list: Vec<String> = failed.iter().map(ToString::to_string).collect();
        line.push_str(&format!("; failed frames: {}", list.join(", ")));
    }
    line
}
