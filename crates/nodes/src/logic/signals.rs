//! Nodes that watch a signal over frames: `Change`, `TogEdge`, `FlipFlop`,
//! `Toggle`, `Counter`, `MonoFlop`.
//!
//! They are state-correct under the runtime's reuse rule: they react to
//! edges (a slice that changed since their last evaluation), which only
//! happen when an input changed, so being reused is right; a one-frame pulse
//! (`Change`, `TogEdge`, Counter's Overflow) or a timed state (`MonoFlop`)
//! asks to run again next frame to end itself.

use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::typed_pins::PinData;
use spreadlight_graph::{
    Choice, Choices, EvalContext, In, Node, NodeDef, NodeError, Out, Registry, SliceValue,
};

const ANIMATION: &str = "Animation";

/// What `Counter` does at its range's ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CounterMode {
    /// Past one end, start again at the other.
    Wrap,
    /// Stop at the ends.
    Clamp,
    /// Ignore the range.
    Unlimited,
}

/// `Counter`'s Mode options, as vvvv names them.
pub static COUNTER_MODE: Choices<CounterMode> = Choices::new(
    "Counter Mode",
    &["Wrap", "Clamp", "Unlimited"],
    &[
        CounterMode::Wrap,
        CounterMode::Clamp,
        CounterMode::Unlimited,
    ],
);

pub fn register(r: &mut Registry) {
    r.add(change::<f32>("Change (Animation)", 0.0));
    r.add(change::<String>("Change (String)", String::new()));
    r.add(
        NodeDef::new(
            "TogEdge (Animation)",
            ANIMATION,
            "Up Edge is true for the one frame in which a slice of Input turns on, Down Edge \
             for the one in which it turns off. A slice starts off.",
        )
        .remembers(1)
        .with_pins_node(|p| {
            let input = p.input("Input", false);
            let up = p.output::<bool>("Up Edge");
            let down = p.output::<bool>("Down Edge");
            move || TogEdge {
                input,
                up,
                down,
                last: Vec::new(),
            }
        }),
    );
    r.add(
        NodeDef::new(
            "FlipFlop (Animation)",
            ANIMATION,
            "Per slice, Output turns on while Set is on and off while Reset is on, and keeps its \
             state otherwise (Reset wins when both are on). Inverse Output is its opposite.",
        )
        .stateful()
        .with_pins_node(|p| {
            let set = p.input("Set", false);
            let reset = p.input("Reset", false);
            let output = p.output::<bool>("Output");
            let inverse = p.output::<bool>("Inverse Output");
            move || FlipFlop {
                set,
                reset,
                output,
                inverse,
                state: Vec::new(),
            }
        }),
    );
    r.add(
        NodeDef::new(
            "Toggle (Animation)",
            ANIMATION,
            "Per slice, Output flips each time Input turns on (a held Input flips once). Reset \
             turns it off.",
        )
        .stateful()
        .with_pins_node(|p| {
            let input = p.input("Input", false);
            let reset = p.input("Reset", false);
            let output = p.output::<bool>("Output");
            move || Toggle {
                input,
                reset,
                output,
                state: Vec::new(),
                last: Vec::new(),
            }
        }),
    );
    r.add(
        NodeDef::new(
            "Counter (Animation)",
            ANIMATION,
            "Per slice, counts up by Increment each time Up turns on and down each time Down \
             turns on (a held pin counts once: a bang or a key press counts one). Mode says what \
             happens past [Minimum, Maximum]: Wrap starts again at the other end, Clamp stops, \
             Unlimited ignores the range. Overflow is true in the frame the count wrapped or hit \
             an end. Reset sets the count to Default.",
        )
        .stateful()
        .with_pins_node(|p| {
            let pins = CounterPins {
                up: p.input("Up", false),
                down: p.input("Down", false),
                increment: p.input("Increment", 1i64),
                minimum: p.input("Minimum", 0i64),
                maximum: p.input("Maximum", 10i64),
                default: p.input("Default", 0i64),
                mode: p.input_choice("Mode", &COUNTER_MODE, CounterMode::Wrap),
                reset: p.input("Reset", false),
                output: p.output::<i64>("Output"),
                overflow: p.output::<bool>("Overflow"),
            };
            move || Counter {
                pins,
                counts: Vec::new(),
                up: Vec::new(),
                down: Vec::new(),
            }
        }),
    );
    r.add(
        NodeDef::new(
            "MonoFlop (Animation)",
            ANIMATION,
            "Per slice, Output turns on when Set turns on and off again Time seconds later. \
             Retriggerable: a new Set while on starts the time again; otherwise it is ignored.",
        )
        .stateful()
        .with_pins_node(|p| {
            let set = p.input("Set", false);
            let time = p.input("Time", 1.0f32);
            let retrigger = p.input("Retriggerable", false);
            let output = p.output::<bool>("Output");
            move || MonoFlop {
                set,
                time,
                retrigger,
                output,
                until: Vec::new(),
                last: Vec::new(),
            }
        }),
    );
}

/// Per slice: whether `now` turned on since `last` (a new slice starts off). Updates `last`.
fn rising_edges(last: &mut Vec<bool>, now: &[bool], n: usize) -> Vec<bool> {
    last.resize(n, false);
    last.iter_mut()
        .enumerate()
        .map(|(i, was)| {
            let is = *wrapped(now, i);
            std::mem::replace(was, is) != is && is
        })
        .collect()
}

fn change<T: SliceValue + PinData<Meta = ()> + PartialEq>(
    name: &'static str,
    default: T,
) -> NodeDef {
    NodeDef::new(
        name,
        ANIMATION,
        "True, per slice, for the one frame in which Input's slice differs from what it was \
         the frame before (a slice that appears counts as changed; the first frame does not).",
    )
    .remembers(1)
    .with_pins_node(|p| {
        let input = p.input("Input", default);
        let output = p.output::<bool>("Output");
        move || Change::<T> {
            input,
            output,
            last: None,
        }
    })
}

struct Change<T: PinData> {
    input: In<T>,
    output: Out<bool>,
    last: Option<Vec<T>>,
}

impl<T: SliceValue + PinData + PartialEq> Node for Change<T> {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let input = cx.get(self.input)?;
        let out: Vec<bool> = match &self.last {
            None => vec![false; input.len()],
            Some(last) => input
                .iter()
                .enumerate()
                .map(|(i, v)| last.get(i) != Some(v))
                .collect(),
        };
        self.last = Some(input.to_vec());
        if out.contains(&true) {
            // The pulse lasts one frame: run again to end it even if nothing changes.
            cx.reevaluate_next_frame();
        }
        cx.put(self.output, out);
        Ok(())
    }
}

struct TogEdge {
    input: In<bool>,
    up: Out<bool>,
    down: Out<bool>,
    last: Vec<bool>,
}

impl Node for TogEdge {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let input = cx.get(self.input)?;
        let before = {
            let mut b = self.last.clone();
            b.resize(input.len(), false);
            b
        };
        let up = rising_edges(&mut self.last, input, input.len());
        let down: Vec<bool> = before.iter().zip(input).map(|(&b, &i)| b && !i).collect();
        if up.contains(&true) || down.contains(&true) {
            cx.reevaluate_next_frame();
        }
        cx.put(self.up, up);
        cx.put(self.down, down);
        Ok(())
    }
}

struct FlipFlop {
    set: In<bool>,
    reset: In<bool>,
    output: Out<bool>,
    inverse: Out<bool>,
    state: Vec<bool>,
}

impl Node for FlipFlop {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let (set, reset) = (cx.get(self.set)?, cx.get(self.reset)?);
        let n = slice_count([set.len(), reset.len()]);
        self.state.resize(n, false);
        for (i, s) in self.state.iter_mut().enumerate() {
            if *wrapped(reset, i) {
                *s = false;
            } else if *wrapped(set, i) {
                *s = true;
            }
        }
        cx.put(self.output, self.state.clone());
        cx.put(self.inverse, self.state.iter().map(|s| !s).collect());
        Ok(())
    }
}

struct Toggle {
    input: In<bool>,
    reset: In<bool>,
    output: Out<bool>,
    state: Vec<bool>,
    last: Vec<bool>,
}

impl Node for Toggle {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let (input, reset) = (cx.get(self.input)?, cx.get(self.reset)?);
        let n = slice_count([input.len(), reset.len()]);
        let edges = rising_edges(&mut self.last, input, n);
        self.state.resize(n, false);
        for (i, s) in self.state.iter_mut().enumerate() {
            if *wrapped(reset, i) {
                *s = false;
            } else if edges[i] {
                *s = !*s;
            }
        }
        cx.put(self.output, self.state.clone());
        Ok(())
    }
}

#[derive(Clone, Copy)]
struct CounterPins {
    up: In<bool>,
    down: In<bool>,
    increment: In<i64>,
    minimum: In<i64>,
    maximum: In<i64>,
    default: In<i64>,
    mode: In<Choice<CounterMode>>,
    reset: In<bool>,
    output: Out<i64>,
    overflow: Out<bool>,
}

struct Counter {
    pins: CounterPins,
    counts: Vec<i64>,
    up: Vec<bool>,
    down: Vec<bool>,
}

/// One counting step: `count + step` with the range rule; returns the new count and whether it overflowed.
fn count_step(count: i64, step: i64, min: i64, max: i64, mode: CounterMode) -> (i64, bool) {
    let (lo, hi) = (min.min(max), min.max(max));
    let next = count.saturating_add(step);
    match mode {
        CounterMode::Unlimited => (next, false),
        CounterMode::Clamp => (next.clamp(lo, hi), next < lo || next > hi),
        CounterMode::Wrap => {
            let span = i128::from(hi) - i128::from(lo) + 1;
            let wrapped = (i128::from(next) - i128::from(lo)).rem_euclid(span) + i128::from(lo);
            (wrapped as i64, next < lo || next > hi)
        }
    }
}

impl Node for Counter {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let (up, down) = (cx.get(pins.up)?, cx.get(pins.down)?);
        let ints: [&[i64]; 4] = [
            cx.get(pins.increment)?,
            cx.get(pins.minimum)?,
            cx.get(pins.maximum)?,
            cx.get(pins.default)?,
        ];
        let modes = cx.choices(pins.mode)?;
        let reset = cx.get(pins.reset)?;
        let n = slice_count(
            [up.len(), down.len(), modes.len(), reset.len()]
                .into_iter()
                .chain(ints.iter().map(|s| s.len())),
        );
        let ups = rising_edges(&mut self.up, up, n);
        let downs = rising_edges(&mut self.down, down, n);
        let mut overflow = vec![false; n];
        let old = self.counts.len();
        for i in 0..n {
            let [inc, min, max, default] = ints.map(|s| *wrapped(s, i));
            if i >= old {
                self.counts.push(default);
            }
            if *wrapped(reset, i) {
                self.counts[i] = default;
                continue;
            }
            let mode = *wrapped(&modes, i);
            for (edge, step) in [(ups[i], inc), (downs[i], inc.saturating_neg())] {
                if edge {
                    let (c, o) = count_step(self.counts[i], step, min, max, mode);
                    self.counts[i] = c;
                    overflow[i] |= o;
                }
            }
        }
        self.counts.truncate(n);
        // Overflow is a one-frame pulse; run again to clear it.
        if overflow.contains(&true) {
            cx.reevaluate_next_frame();
        }
        cx.put(pins.output, self.counts.clone());
        cx.put(pins.overflow, overflow);
        Ok(())
    }
}

struct MonoFlop {
    set: In<bool>,
    time: In<f32>,
    retrigger: In<bool>,
    output: Out<bool>,
    /// Per slice, the clock time at which it turns off (None: off).
    until: Vec<Option<f64>>,
    last: Vec<bool>,
}

impl Node for MonoFlop {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let (set, time, retrigger) = (
            cx.get(self.set)?,
            cx.get(self.time)?,
            cx.get(self.retrigger)?,
        );
        let n = slice_count([set.len(), time.len(), retrigger.len()]);
        let edges = rising_edges(&mut self.last, set, n);
        self.until.resize(n, None);
        let now = cx.clock.time;
        let mut out = Vec::with_capacity(n);
        for (i, until) in self.until.iter_mut().enumerate() {
            // A microsecond of slack, so that frame times summed in floating point end on time.
            if until.is_some_and(|t| now + 1e-6 >= t) {
                *until = None;
            }
            if edges[i] && (until.is_none() || *wrapped(retrigger, i)) {
                let duration = f64::from(*wrapped(time, i)).max(0.0);
                *until = Some(now + duration).filter(|_| duration > 0.0);
            }
            out.push(until.is_some());
        }
        if out.contains(&true) {
            // Turning off is a matter of time, not of inputs.
            cx.reevaluate_next_frame();
        }
        cx.put(self.output, out);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use spreadlight_graph::NodeRun;

    use crate::testing::{Harness, floats, ints, option};

    #[test]
    fn change_pulses_for_one_frame() {
        let mut h = Harness::new("Change (Animation)");
        h.set("Input", floats(&[1.0, 2.0]));
        assert_eq!(h.next::<bool>("Output"), [false, false]);
        h.set("Input", floats(&[1.0, 3.0]));
        assert_eq!(h.next::<bool>("Output"), [false, true]);
        // Nothing changes upstream, but the pulse must end.
        assert_eq!(h.next::<bool>("Output"), [false, false]);
        assert_eq!(h.step(), NodeRun::Reused);
    }

    #[test]
    fn togedge_and_toggle_see_edges_once() {
        let mut edge = Harness::new("TogEdge (Animation)");
        let mut toggle = Harness::new("Toggle (Animation)");
        let mut frames = Vec::new();
        for input in [false, true, true, true, false, false, true] {
            edge.set("Input", vec![input]);
            toggle.set("Input", vec![input]);
            edge.step();
            frames.push((
                edge.out::<bool>("Up Edge")[0],
                edge.out::<bool>("Down Edge")[0],
                toggle.next::<bool>("Output")[0],
            ));
        }
        assert_eq!(
            frames,
            [
                (false, false, false),
                (true, false, true),
                (false, false, true),
                (false, false, true),
                (false, true, true),
                (false, false, true),
                (true, false, false),
            ]
        );
    }

    #[test]
    fn flipflop_holds_between_set_and_reset() {
        let mut h = Harness::new("FlipFlop (Animation)");
        let mut seen = Vec::new();
        for (set, reset) in [
            (false, false),
            (true, false),
            (false, false),
            (false, true),
            (true, true),
            (false, false),
        ] {
            h.set("Set", vec![set]).set("Reset", vec![reset]);
            seen.push(h.next::<bool>("Output")[0]);
        }
        assert_eq!(seen, [false, true, true, false, false, false]);
        assert_eq!(h.step(), NodeRun::Reused);
        assert_eq!(h.out::<bool>("Inverse Output"), [true]);
    }

    #[test]
    fn counter_counts_edges_and_wraps() {
        let mut h = Harness::new("Counter (Animation)");
        h.set("Maximum", ints(&[2]));
        let mut seen = Vec::new();
        for up in [true, false, true, true, false, true, false, true] {
            h.set("Up", vec![up]);
            h.step();
            seen.push((h.out::<i64>("Output")[0], h.out::<bool>("Overflow")[0]));
        }
        // Edges at frames 0, 2, 5, 7: 1, 2, wrap to 0, 1. A held Up (frame 3) counts once.
        assert_eq!(
            seen,
            [
                (1, false),
                (1, false),
                (2, false),
                (2, false),
                (2, false),
                (0, true),
                (0, false),
                (1, false)
            ]
        );
        h.set("Mode", option("Clamp")).set("Up", vec![false]);
        h.step();
        for _ in 0..3 {
            h.set("Up", vec![true]);
            h.step();
            h.set("Up", vec![false]);
            h.step();
        }
        assert_eq!(h.out::<i64>("Output"), [2]);
        h.set("Down", vec![true]);
        assert_eq!(h.next::<i64>("Output"), [1]);
        h.set("Reset", vec![true]);
        assert_eq!(h.next::<i64>("Output"), [0]);
    }

    #[test]
    fn monoflop_turns_itself_off_in_time() {
        let mut h = Harness::new("MonoFlop (Animation)");
        // 60 fps: 0.05 s is three frames.
        h.set("Time", floats(&[0.05]));
        assert_eq!(h.next::<bool>("Output"), [false]);
        h.set("Set", vec![true]);
        let mut seen = Vec::new();
        for _ in 0..6 {
            seen.push(h.next::<bool>("Output")[0]);
        }
        assert_eq!(seen, [true, true, true, false, false, false]);
        assert_eq!(h.step(), NodeRun::Reused);
    }
}
