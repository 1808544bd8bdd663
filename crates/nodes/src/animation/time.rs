//! The clock as nodes: `Time (Animation)` (seconds, frame number and frame
//! delta of the running patch) and `Stopwatch (Animation)`.

use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::{EvalContext, Node, NodeDef, NodeError, Registry};

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
        .output::<f32>("Time")
        .output::<i64>("Frame")
        .output::<f32>("Delta")
        .time_dependent()
        .evaluate(|cx| {
            let clock = *cx.clock;
            cx.set(0, vec![clock.time as f32]);
            cx.set(1, vec![i64::try_from(clock.frame).unwrap_or(i64::MAX)]);
            cx.set(2, vec![clock.delta as f32]);
            Ok(())
        }),
    );
    r.add(
        NodeDef::new(
            "Stopwatch (Animation)",
            CATEGORY,
            "Per slice, counts seconds while Run is on and holds while it is off; Reset sets it \
             back to 0.",
        )
        .input("Run", false)
        .input("Reset", false)
        .output::<f32>("Time")
        .construct(|| Stopwatch {
            elapsed: Vec::new(),
        }),
    );
}

struct Stopwatch {
    /// Seconds per slice, in f64 so long runs keep their precision.
    elapsed: Vec<f64>,
}

impl Node for Stopwatch {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let (run, reset) = (cx.slices::<bool>(0)?, cx.slices::<bool>(1)?);
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
        cx.set(0, self.elapsed.iter().map(|&t| t as f32).collect());
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use spreadlight_graph::NodeRun;

    use crate::testing::{Harness, assert_close};

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
