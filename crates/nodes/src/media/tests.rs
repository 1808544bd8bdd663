//! The media nodes in running patches, on generated sound files: the
//! analyses' answers, determinism across render chunks, errors that name the
//! file while the rest runs on, and no decoding without a sink.

use std::f32::consts::TAU;
use std::path::Path;
use std::sync::Arc;

use spreadlight_graph::{FrameClock, NodeDoc, NodeId, NodeRun, Patch, PatchDir, Runtime, Spread};

/// Write mono `samples` at `rate` as a 16-bit WAV file.
fn write_wav(path: &Path, samples: &[f32], rate: u32) {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: rate,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).expect("create wav");
    for s in samples {
        w.write_sample((s.clamp(-1.0, 1.0) * 32767.0).round() as i16)
            .expect("sample");
    }
    w.finalize().expect("finish wav");
}

fn sine(freq: f32, amplitude: f32, rate: u32, seconds: f32) -> Vec<f32> {
    (0..(seconds * rate as f32) as usize)
        .map(|i| amplitude * (TAU * freq * i as f32 / rate as f32).sin())
        .collect()
}

/// Clicks (5 ms decaying bursts) at `bpm`.
fn clicks(bpm: f32, rate: u32, seconds: f32) -> Vec<f32> {
    let mut out = vec![0.0; (seconds * rate as f32) as usize];
    let period = (60.0 / bpm * rate as f32) as usize;
    for start in (0..out.len()).step_by(period) {
        for k in 0..(0.005 * rate as f32) as usize {
            let t = k as f32 / rate as f32;
            if let Some(s) = out.get_mut(start + k) {
                *s = 0.9 * (TAU * 1000.0 * t).sin() * (-t / 0.002).exp();
            }
        }
    }
    out
}

/// A patch in `dir`: `AudioFile` (node 1) on `file`, `analysis` (node 2)
/// fed by it with its first output probed (node 3), and an unrelated
/// `LinearSpread` probed (nodes 4, 5) to show the rest runs on.
fn patch(file: &str, analysis: &str, values: &[(&str, Spread)]) -> Patch {
    let mut patch = Patch::default();
    patch.add(NodeDoc::new(1, "AudioFile").with("Filename", vec![file.to_owned()]));
    let mut node = NodeDoc::new(2, analysis);
    for (pin, value) in values {
        node.values.insert((*pin).to_owned(), value.clone());
    }
    patch.add(node);
    patch.link(1, "Audio", 2, "Audio");
    patch.add(NodeDoc::new(3, "Probe").with("Name", vec!["analysis".to_owned()]));
    let registry = crate::registry();
    let first = &registry
        .get(analysis)
        .and_then(|def| def.outputs.first())
        .expect("analysis node with an output")
        .name;
    patch.link(2, first, 3, "Input");
    patch.add(NodeDoc::new(4, "LinearSpread"));
    patch.add(NodeDoc::new(5, "Probe").with("Name", vec!["other".to_owned()]));
    patch.link(4, "Output", 5, "Input");
    patch
}

fn runtime(dir: &Path, patch: &Patch) -> Runtime {
    let mut rt = Runtime::new(crate::registry());
    rt.provide(Arc::new(PatchDir(dir.to_path_buf())));
    let problems = rt.load(patch);
    assert!(problems.is_empty(), "{problems:?}");
    rt
}

fn floats(rt: &Runtime, node: u32, pin: &str) -> Vec<f32> {
    match rt.output(NodeId(node), pin).map(|s| s.as_ref().clone()) {
        Some(Spread::Float(v)) => v,
        other => panic!("{node}.{pin}: {other:?}"),
    }
}

/// Evaluate frames `from..=to` at `fps`; the outputs are frame `to`'s.
fn run(rt: &mut Runtime, from: u64, to: u64, fps: f64) {
    for f in from..=to {
        rt.evaluate(FrameClock::fixed(f, fps));
    }
}

#[test]
fn a_tone_file_gives_its_level_and_peaks_in_its_band() {
    let dir = tempfile::tempdir().expect("tempdir");
    write_wav(
        &dir.path().join("a440.wav"),
        &sine(440.0, 0.5, 22050, 1.0),
        22050,
    );
    // Spectrum: 8 octave bands from 27.5 Hz; 440 Hz starts the fifth (440..880).
    let p = patch(
        "a440.wav",
        "Spectrum",
        &[
            ("Bands", Spread::Int(vec![8])),
            ("Min Frequency", Spread::Float(vec![27.5])),
            ("Max Frequency", Spread::Float(vec![7040.0])),
        ],
    );
    let mut rt = runtime(dir.path(), &p);
    run(&mut rt, 0, 30, 60.0);
    let bands = floats(&rt, 2, "Bands");
    assert_eq!(bands.len(), 8);
    let loudest = bands
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, _)| i);
    assert!(matches!(loudest, Some(3 | 4)), "{bands:?}");
    assert!(bands[3].max(bands[4]) > 0.4, "{bands:?}");
    assert!(bands[0] < 0.01 && bands[7] < 0.01, "{bands:?}");
    assert!((floats(&rt, 1, "Position")[0] - 0.5).abs() < 1e-6);
    assert!((floats(&rt, 1, "Duration")[0] - 1.0).abs() < 1e-6);

    let p = patch("a440.wav", "Level", &[]);
    let mut rt = runtime(dir.path(), &p);
    run(&mut rt, 0, 30, 60.0);
    let rms = floats(&rt, 2, "RMS")[0];
    let peak = floats(&rt, 2, "Peak")[0];
    assert!((rms - 0.5 / 2f32.sqrt()).abs() < 0.005, "{rms}");
    assert!((peak - 0.5).abs() < 0.005, "{peak}");
    // Past the end (no Loop) the sound is silent.
    run(&mut rt, 70, 70, 60.0);
    assert_eq!(floats(&rt, 2, "RMS"), [0.0]);
}

#[test]
fn a_click_track_file_gives_120_bpm_and_a_chunk_equals_a_full_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    write_wav(
        &dir.path().join("clicks.wav"),
        &clicks(120.0, 22050, 6.0),
        22050,
    );
    let p = patch(
        "clicks.wav",
        "Beat",
        &[("Window", Spread::Float(vec![4.0]))],
    );
    // A full run from frame 0 at 10 fps, and a chunk that starts at frame 45.
    let mut full = runtime(dir.path(), &p);
    let mut onsets = 0;
    for f in 0..=50 {
        full.evaluate(FrameClock::fixed(f, 10.0));
        if let Some(Spread::Bool(b)) = full.output(NodeId(2), "Onset").map(|s| s.as_ref().clone()) {
            onsets += usize::from(b[0]);
        }
    }
    let bpm = floats(&full, 2, "BPM")[0];
    assert!((bpm - 120.0).abs() < 1.0, "{bpm}");
    // Two clicks a second for five seconds, each flagged in one frame.
    assert!((9..=11).contains(&onsets), "{onsets}");
    let mut chunk = runtime(dir.path(), &p);
    run(&mut chunk, 45, 50, 10.0);
    for pin in ["BPM", "Strength"] {
        assert_eq!(floats(&full, 2, pin), floats(&chunk, 2, pin), "{pin}");
    }
    assert_eq!(
        full.output(NodeId(2), "Onset"),
        chunk.output(NodeId(2), "Onset")
    );
}

#[test]
fn an_envelope_rises_with_its_attack_and_falls_with_its_release() {
    let dir = tempfile::tempdir().expect("tempdir");
    // Half a second at a steady 0.8, then half a second of silence.
    let mut steps = vec![0.8f32; 11025];
    steps.extend(vec![0.0; 11025]);
    write_wav(&dir.path().join("step.wav"), &steps, 22050);
    let p = patch(
        "step.wav",
        "Envelope",
        &[
            ("Attack", Spread::Float(vec![0.05])),
            ("Release", Spread::Float(vec![0.1])),
        ],
    );
    let mut rt = runtime(dir.path(), &p);
    // One attack time after the step up (frame 3 at 60 fps): 63% of 0.8.
    run(&mut rt, 3, 3, 60.0);
    let up = floats(&rt, 2, "Envelope")[0];
    assert!((up - 0.8 * (1.0 - (-1.0f32).exp())).abs() < 0.005, "{up}");
    // One release time after the step down (0.6 s): 37% of 0.8.
    run(&mut rt, 36, 36, 60.0);
    let down = floats(&rt, 2, "Envelope")[0];
    assert!((down - 0.8 * (-1.0f32).exp()).abs() < 0.005, "{down}");
}

#[test]
fn bad_files_are_errors_naming_the_file_and_the_rest_runs_on() {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("garbage.wav"), b"no sound here".repeat(40)).expect("write");
    write_wav(
        &dir.path().join("whole.wav"),
        &sine(440.0, 0.5, 8000, 1.0),
        8000,
    );
    let bytes = std::fs::read(dir.path().join("whole.wav")).expect("read");
    std::fs::write(dir.path().join("cut.wav"), &bytes[..bytes.len() / 3]).expect("write");
    for file in ["missing.wav", "garbage.wav", "cut.wav"] {
        let mut rt = runtime(dir.path(), &patch(file, "Level", &[]));
        run(&mut rt, 0, 1, 60.0);
        let error = rt.node_error(NodeId(1)).map(ToString::to_string);
        assert!(
            error
                .as_deref()
                .is_some_and(|e| e.contains(file) && e.contains("Filename")),
            "{file}: {error:?}"
        );
        // Nothing flows from the failed node, and the unrelated probe has its value.
        assert_eq!(floats(&rt, 2, "RMS"), Vec::<f32>::new());
        assert!(!floats(&rt, 4, "Output").is_empty());
    }
}

#[test]
fn nothing_decodes_for_a_node_that_feeds_no_sink() {
    let dir = tempfile::tempdir().expect("tempdir");
    // A garbage file shows whether decoding was tried: it would fail.
    std::fs::write(dir.path().join("garbage.wav"), b"no sound here".repeat(40)).expect("write");
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "AudioFile").with("Filename", vec!["garbage.wav".to_owned()]));
    p.add(NodeDoc::new(2, "Level"));
    p.link(1, "Audio", 2, "Audio");
    let mut rt = runtime(dir.path(), &p);
    run(&mut rt, 0, 2, 60.0);
    assert_eq!(
        rt.stats().node(NodeId(1)).map(|n| n.run),
        Some(NodeRun::Skipped)
    );
    assert!(rt.node_error(NodeId(1)).is_none());
    // Probe the level: now it decodes, and fails.
    p.add(NodeDoc::new(3, "Probe"));
    p.link(2, "RMS", 3, "Input");
    let mut rt = runtime(dir.path(), &p);
    run(&mut rt, 0, 0, 60.0);
    assert_eq!(
        rt.stats().node(NodeId(1)).map(|n| n.run),
        Some(NodeRun::Failed)
    );
}

#[test]
fn devices_the_machine_lacks_are_errors_on_their_nodes_and_the_rest_runs_on() {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "AudioIn"));
    p.add(NodeDoc::new(2, "Level"));
    p.link(1, "Audio", 2, "Audio");
    p.add(NodeDoc::new(3, "Probe"));
    p.link(2, "RMS", 3, "Input");
    p.add(NodeDoc::new(4, "MidiIn"));
    p.add(NodeDoc::new(5, "Probe"));
    p.link(4, "Value", 5, "Input");
    p.add(NodeDoc::new(6, "LinearSpread"));
    p.add(NodeDoc::new(7, "Probe"));
    p.link(6, "Output", 7, "Input");
    let mut rt = Runtime::new(crate::registry());
    assert!(rt.load(&p).is_empty());
    run(&mut rt, 0, 1, 60.0);
    // A machine with the devices runs the nodes; one without says so on each.
    if let Some(e) = rt.node_error(NodeId(1)) {
        assert!(e.to_string().starts_with("no audio device"), "{e}");
    }
    if let Some(e) = rt.node_error(NodeId(4)) {
        let e = e.to_string();
        assert!(
            e.contains("no MIDI sequencer device") || e.contains("no MIDI input port"),
            "{e}"
        );
    }
    assert!(!floats(&rt, 6, "Output").is_empty());
    assert_eq!(rt.stats().failed, rt.node_errors().count());
}
