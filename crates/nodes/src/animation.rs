//! Nodes that move with time: `LFO` here; easing and keyframes
//! (`animation/easing.rs`), noise (`animation/noise.rs`) and the clock as
//! nodes (`animation/time.rs`) beside it. The LFO depends on the frame clock,
//! so the runtime evaluates it every frame.

use spreadlight_graph::{EvalContext, Node, NodeDef, NodeError, Registry, spread};

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
             Pause holds it, Reset sets it to 0. A Period of zero or less holds the phase (no NaN).",
        )
        .input("Period", 1.0f32)
        .input("Pause", false)
        .input("Reset", false)
        .output::<f32>("Output")
        .output::<i64>("Cycles")
        .time_dependent()
        .construct(Lfo::default),
    );
}

/// Keeps an unwrapped phase per slice, in f64 so long runs stay exact.
#[derive(Default)]
struct Lfo {
    phases: Vec<f64>,
}

impl Node for Lfo {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let (period, pause, reset) = (
            cx.slices::<f32>(0)?,
            cx.slices::<bool>(1)?,
            cx.slices::<bool>(2)?,
        );
        let n = spread::slice_count([period.len(), pause.len(), reset.len()]);
        self.phases.resize(n, 0.0);
        let delta = cx.clock.delta;
        let pins = spread::cycled(period, n)
            .zip(spread::cycled(pause, n))
            .zip(spread::cycled(reset, n));
        for (phase, ((&period, &pause), &reset)) in self.phases.iter_mut().zip(pins) {
            let p = f64::from(period);
            if reset {
                *phase = 0.0;
            } else if !pause && p > 0.0 && p.is_finite() {
                *phase += delta / p;
            }
        }
        let output = self.phases.iter().map(|p| p.fract() as f32).collect();
        let cycles = self.phases.iter().map(|p| p.floor() as i64).collect();
        cx.set::<f32>(0, output);
        cx.set::<i64>(1, cycles);
        Ok(())
    }
}
