//! Nodes that move with time: `LFO` here; easing and keyframes
//! (`animation/easing.rs`), noise (`animation/noise.rs`) and the clock as
//! nodes (`animation/time.rs`) beside it. The LFO depends on the frame clock,
//! so the runtime evaluates it every frame.

use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Registry, spread};

pub mod easing;
pub mod noise;
pub mod time;

pub fn register(r: &mut Registry) {
    easing::register(r);
    noise::register(r);
    time::register(r);
    r.add(
        NodeDef::new(
            "LFO",
            "Animation",
            "Low-frequency oscillator: a phase running from 0 to 1 once per Period seconds, per slice. \
             Pause holds it, Reset sets it to 0. A new LFO starts at the phase \
             one running since time 0 would have (so a render of frames 100.. sees what a full run sees). A Period of zero or less holds the phase (no NaN).",
        )
        .time_dependent()
        // Not `stateful`: a new LFO seeds its phase from the clock, so a render from frame N
        // matches a run from 0 while Period, Pause and Reset are constant (patches/lfo-sine.ron).
        .with_pins_node(|p| {
            let period = p.input("Period", 1.0f32);
            let pause = p.input("Pause", false);
            let reset = p.input("Reset", false);
            let output = p.output::<f32>("Output");
            let cycles = p.output::<i64>("Cycles");
            move || Lfo {
                period,
                pause,
                reset,
                output,
                cycles,
                phases: Vec::new(),
            }
        }),
    );
}

/// Keeps an unwrapped phase per slice, in f64 so long runs stay exact.
struct Lfo {
    period: In<f32>,
    pause: In<bool>,
    reset: In<bool>,
    output: Out<f32>,
    cycles: Out<i64>,
    phases: Vec<f64>,
}

impl Node for Lfo {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let (period, pause, reset) = (
            cx.get(self.period)?,
            cx.get(self.pause)?,
            cx.get(self.reset)?,
        );
        let n = spread::slice_count([period.len(), pause.len(), reset.len()]);
        let delta = cx.clock.delta;
        // A new slice starts where one running since time 0 would be: a render
        // that begins at frame N (a farm's chunk) sees the phase a full run does.
        let fresh = self.phases.len();
        self.phases.resize(n, (cx.clock.time - delta).max(0.0));
        let pins = spread::cycled(period, n)
            .zip(spread::cycled(pause, n))
            .zip(spread::cycled(reset, n));
        for (i, (phase, ((&period, &pause), &reset))) in
            self.phases.iter_mut().zip(pins).enumerate()
        {
            let p = f64::from(period);
            if i >= fresh {
                // Seeded with the time before this frame: in cycles of this period, or held.
                *phase = if pause || !(p > 0.0 && p.is_finite()) {
                    0.0
                } else {
                    *phase / p
                };
            }
            if reset {
                *phase = 0.0;
            } else if !pause && p > 0.0 && p.is_finite() {
                *phase += delta / p;
            }
        }
        let output = self.phases.iter().map(|p| p.fract() as f32).collect();
        let cycles = self.phases.iter().map(|p| p.floor() as i64).collect();
        cx.put(self.output, output);
        cx.put(self.cycles, cycles);
        Ok(())
    }
}
