//! The clock as nodes: `Time (Animation)` (seconds, frame number and frame
//! delta of the running patch), `Stopwatch (Animation)` and `Timeliner
//! (Animation)`, a transport (play, speed, seek, loop) whose Time plays
//! `Keyframes` tracks as vvvv's Timeliner does.

use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Registry};

const CATEGORY: &str = "Animation";

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Time (Animation)",
            CATEGORY,
            "The patch's clock: Time in seconds since the start, Frame (0 in the first frame) \
             and Delta, the seconds since the previous frame. Headless runs step a fixed frame \
             rate, so these are exact there; the editor uses wall time.",
        )
        .time_dependent()
        .with_pins(|p| {
            let time = p.output::<f32>("Time");
            let frame = p.output::<i64>("Frame");
            let delta = p.output::<f32>("Delta");
            move |cx| {
                let clock = *cx.clock;
                cx.put(time, vec![clock.time as f32]);
                cx.put(frame, vec![i64::try_from(clock.frame).unwrap_or(i64::MAX)]);
                cx.put(delta, vec![clock.delta as f32]);
                Ok(())
            }
        }),
    );
    r.add(
        NodeDef::new(
            "Stopwatch (Animation)",
            CATEGORY,
            "Per slice, counts seconds while Run is on and holds while it is off; Reset sets it \
             back to 0.",
        )
        .stateful()
        .with_pins_node(|p| {
            let run = p.input("Run", false);
            let reset = p.input("Reset", false);
            let time = p.output::<f32>("Time");
            move || Stopwatch {
                run,
                reset,
                time,
                elapsed: Vec::new(),
            }
        }),
    );
    r.add(timeliner());
}

/// The transport of a keyframe timeline.
fn timeliner() -> NodeDef {
    NodeDef::new(
        "Timeliner (Animation)",
        CATEGORY,
        "A timeline transport, per slice: while Play is on, Time runs at Speed (1: real time, \
         2: double, negative: backwards); Seek jumps to Seek Time (and holds there while on); \
         with Loop on, Time wraps around within [Loop Start, Loop End). Feed Time into \
         Keyframes nodes for Timeliner-style tracks. Playing says whether it moves.",
    )
    .stateful()
    .with_pins_node(|p| {
        let pins = TimelinerPins {
            play: p.input("Play", false),
            speed: p.input("Speed", 1.0f32),
            seek: p.input("Seek", false),
            seek_time: p.input("Seek Time", 0.0f32),
            looping: p.input("Loop", false),
            loop_start: p.input("Loop Start", 0.0f32),
            loop_end: p.input("Loop End", 10.0f32),
            time: p.output::<f32>("Time"),
            playing: p.output::<bool>("Playing"),
        };
        move || Timeliner {
            pins,
            time: Vec::new(),
        }
    })
}

#[derive(Clone, Copy)]
struct TimelinerPins {
    play: In<bool>,
    speed: In<f32>,
    seek: In<bool>,
    seek_time: In<f32>,
    looping: In<bool>,
    loop_start: In<f32>,
    loop_end: In<f32>,
    time: Out<f32>,
    playing: Out<bool>,
}

struct Timeliner {
    pins: TimelinerPins,
    time: Vec<f64>,
}

impl Node for Timeliner {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let (play, seek, looping) = (
            cx.get(pins.play)?,
            cx.get(pins.seek)?,
            cx.get(pins.looping)?,
        );
        let floats = [
            cx.get(pins.speed)?,
            cx.get(pins.seek_time)?,
            cx.get(pins.loop_start)?,
            cx.get(pins.loop_end)?,
        ];
        let n = slice_count(
            [play.len(), seek.len(), looping.len()]
                .into_iter()
                .chain(floats.iter().map(|f| f.len())),
        );
        self.time.resize(n, 0.0);
        let mut playing = Vec::with_capacity(n);
        for (i, t) in self.time.iter_mut().enumerate() {
            let [speed, seek_time, start, end] = floats.map(|f| f64::from(*wrapped(f, i)));
            let moving = *wrapped(play, i) && !*wrapped(seek, i) && speed != 0.0;
            if *wrapped(seek, i) {
                *t = seek_time;
            } else if moving {
                *t += cx.clock.delta * speed;
            }
            if *wrapped(looping, i) && end > start {
                *t = start + (*t - start).rem_euclid(end - start);
            }
            if !t.is_finite() {
                *t = 0.0;
            }
            playing.push(moving);
        }
        if playing.contains(&true) {
            // Time moves on without any input changing.
            cx.reevaluate_next_frame();
        }
        cx.put(pins.time, self.time.iter().map(|&t| t as f32).collect());
        cx.put(pins.playing, playing);
        Ok(())
    }
}

struct Stopwatch {
    run: In<bool>,
    reset: In<bool>,
    time: Out<f32>,
    /// Seconds per slice, in f64 so long runs keep their precision.
    elapsed: Vec<f64>,
}

impl Node for Stopwatch {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let (run, reset) = (cx.get(self.run)?, cx.get(self.reset)?);
        let n = slice_count([run.len(), reset.len()]);
        self.elapsed.resize(n, 0.0);
        let mut running = false;
        for (i, t) in self.elapsed.iter_mut().enumerate() {
            if *wrapped(reset, i) {
                *t = 0.0;
            } else if *wrapped(run, i) {
                *t += cx.clock.delta;
                running = true;
            }
        }
        if running {
            // Time passes without any input changing.
            cx.reevaluate_next_frame();
        }
        cx.put(self.time, self.elapsed.iter().map(|&t| t as f32).collect());
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use spreadlight_graph::NodeRun;

    use crate::testing::{Harness, assert_close, floats};

    #[test]
    fn time_reads_the_clock() {
        let mut h = Harness::new("Time (Animation)");
        h.step();
        h.step();
        assert_eq!(h.next::<i64>("Frame"), [2]);
        assert_close(&h.out::<f32>("Time"), &[2.0 / 60.0], 1e-6);
        assert_close(&h.out::<f32>("Delta"), &[1.0 / 60.0], 1e-6);
    }

    #[test]
    fn timeliner_plays_seeks_and_loops() {
        let mut h = Harness::new("Timeliner (Animation)");
        h.step();
        h.set("Play", vec![true]).set("Speed", floats(&[2.0]));
        for _ in 0..30 {
            h.step();
        }
        // Half a second at double speed.
        assert_close(&h.out::<f32>("Time"), &[1.0], 1e-5);
        h.set("Seek", vec![true]).set("Seek Time", floats(&[9.5]));
        assert_eq!(h.next::<f32>("Time"), [9.5]);
        assert_eq!(h.out::<bool>("Playing"), [false]);
        h.set("Seek", vec![false]).set("Loop", vec![true]);
        for _ in 0..30 {
            h.step();
        }
        // 9.5 + 1.0 wraps within [0, 10) to 0.5.
        assert_close(&h.out::<f32>("Time"), &[0.5], 1e-4);
        h.set("Play", vec![false]);
        h.step();
        assert_eq!(h.step(), NodeRun::Reused);
    }

    #[test]
    fn stopwatch_runs_holds_and_resets() {
        let mut h = Harness::new("Stopwatch (Animation)");
        h.step();
        h.set("Run", vec![true]);
        for _ in 0..6 {
            h.step();
        }
        assert_close(&h.out::<f32>("Time"), &[0.1], 1e-6);
        h.set("Run", vec![false]);
        h.step();
        assert_eq!(h.step(), NodeRun::Reused);
        assert_close(&h.out::<f32>("Time"), &[0.1], 1e-6);
        h.set("Reset", vec![true]);
        assert_eq!(h.next::<f32>("Time"), [0.0]);
    }
}
