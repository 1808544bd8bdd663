//! Filters that move an output towards a goal over time: `Damper`
//! (exponential), `LinearFilter` (constant speed), `Oscillator` (a damped
//! spring, overshooting) for values and 2d/3d/4d vectors, and `Decay` (an
//! envelope: quick attack, slow release) for values.
//!
//! They are not time-dependent nodes: while a slice is still moving the node
//! asks to run next frame (`reevaluate_next_frame`); once every slice has
//! settled on its goal it stops asking, and the runtime reuses it until the
//! goal changes. A new slice starts at its goal.

use std::ops::{Add, Mul, Sub};

use glam::{Vec2, Vec3, Vec4};
use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Registry};

use crate::typed::Value;

const CATEGORY: &str = "Animation";

/// A value a filter can move: values and vectors.
pub(crate) trait Linear:
    Value + Copy + PartialEq + Add<Output = Self> + Sub<Output = Self> + Mul<f32, Output = Self>
{
    const ZERO: Self;
    fn length(self) -> f32;
}

impl Linear for f32 {
    const ZERO: Self = 0.0;
    fn length(self) -> f32 {
        self.abs()
    }
}

macro_rules! linear_vector {
    ($t:ty) => {
        impl Linear for $t {
            const ZERO: Self = <$t>::ZERO;
            fn length(self) -> f32 {
                <$t>::length(self)
            }
        }
    };
}
linear_vector!(Vec2);
linear_vector!(Vec3);
linear_vector!(Vec4);

/// A goal the filter can move towards: a non-finite one (NaN from upstream)
/// would poison the filter's state for good, so the slice holds where it is.
fn usable<T: Linear>(goal: T, current: Option<T>) -> T {
    if goal.length().is_finite() {
        goal
    } else {
        current.unwrap_or(T::ZERO)
    }
}

/// Whether `x` is close enough to `goal` to snap onto it and stop moving.
fn settled<T: Linear>(x: T, goal: T) -> bool {
    (goal - x).length() <= 1e-5 * (1.0 + goal.length())
}

pub fn register(r: &mut Registry) {
    r.add(damper::<f32>("Damper (Animation)"));
    r.add(damper::<Vec2>("Damper (2d)"));
    r.add(damper::<Vec3>("Damper (3d)"));
    r.add(damper::<Vec4>("Damper (4d)"));
    r.add(linear_filter::<f32>("LinearFilter (Animation)"));
    r.add(linear_filter::<Vec2>("LinearFilter (2d)"));
    r.add(linear_filter::<Vec3>("LinearFilter (3d)"));
    r.add(linear_filter::<Vec4>("LinearFilter (4d)"));
    r.add(oscillator::<f32>("Oscillator (Animation)"));
    r.add(oscillator::<Vec2>("Oscillator (2d)"));
    r.add(oscillator::<Vec3>("Oscillator (3d)"));
    r.add(oscillator::<Vec4>("Oscillator (4d)"));
    r.add(
        NodeDef::new(
            "Decay (Animation)",
            CATEGORY,
            "An envelope follower: where Input is above Output, Output rises towards it with \
             Attack seconds; where it is below, Output falls with Decay seconds (each the time to \
             come within 1% of Input; 0 follows at once). A peak meter or a smoothed trigger.",
        )
        .stateful()
        .with_pins_node(|p| {
            let input = p.input("Input", 0.0f32);
            let attack = p.input("Attack", 0.0f32);
            let decay = p.input("Decay", 1.0f32);
            let output = p.output::<f32>("Output");
            move || Decay {
                input,
                attack,
                decay,
                output,
                state: Vec::new(),
            }
        }),
    );
}

/// The fraction of the way to the goal that an exponential filter with `time`
/// seconds to within 1% covers in `dt` seconds (1 for a zero or negative time).
fn exp_step(time: f32, dt: f64) -> f32 {
    if time <= 0.0 || !time.is_finite() {
        return 1.0;
    }
    (1.0 - (-dt * 100f64.ln() / f64::from(time)).exp()) as f32
}

fn damper<T: Linear>(name: &'static str) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Follows Goal Position smoothly: each frame Position moves a fixed fraction of the way \
         there, so it comes within 1% of a new goal after Filter Time seconds (0: at once). \
         Velocity is Position's change per second. \
         The 4d variant moves colours too: Color pins link to and from 4d vectors.",
    )
    .stateful()
    .with_pins_node(|p| {
        let goal = p.input("Goal Position", T::ZERO);
        let time = p.input("Filter Time", 1.0f32);
        let position = p.output::<T>("Position");
        let velocity = p.output::<T>("Velocity");
        move || Damper::<T> {
            goal,
            time,
            position,
            velocity,
            state: Vec::new(),
        }
    })
}

struct Damper<T: Linear> {
    goal: In<T>,
    time: In<f32>,
    position: Out<T>,
    velocity: Out<T>,
    state: Vec<T>,
}

impl<T: Linear> Node for Damper<T> {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let (goal, time) = (cx.get(self.goal)?, cx.get(self.time)?);
        let n = slice_count([goal.len(), time.len()]);
        let dt = cx.clock.delta;
        let (mut moving, mut velocity) = (false, Vec::with_capacity(n));
        for i in 0..n {
            let g = usable(*wrapped(goal, i), self.state.get(i).copied());
            if i >= self.state.len() {
                self.state.push(g);
            }
            let x = self.state[i];
            let mut next = x + (g - x) * exp_step(*wrapped(time, i), dt);
            if settled(next, g) {
                next = g;
            } else {
                moving = true;
            }
            velocity.push(per_second(next - x, dt));
            self.state[i] = next;
        }
        self.state.truncate(n);
        if moving {
            cx.reevaluate_next_frame();
        }
        cx.put(self.position, self.state.clone());
        cx.put(self.velocity, velocity);
        Ok(())
    }
}

/// A change over one frame as a rate per second (zero in a frame with no time).
fn per_second<T: Linear>(change: T, dt: f64) -> T {
    if dt > 0.0 {
        change * (1.0 / dt) as f32
    } else {
        T::ZERO
    }
}

fn linear_filter<T: Linear>(name: &'static str) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Moves Position to Goal Position in a straight line at constant speed, arriving Filter \
         Time seconds after the goal changed (0: at once). A goal that changes on the way starts \
         a new move from where Position is. \
         The 4d variant moves colours too: Color pins link to and from 4d vectors.",
    )
    .stateful()
    .with_pins_node(|p| {
        let goal = p.input("Goal Position", T::ZERO);
        let time = p.input("Filter Time", 1.0f32);
        let position = p.output::<T>("Position");
        move || LinearFilter::<T> {
            goal,
            time,
            position,
            state: Vec::new(),
        }
    })
}

/// A linear move: where it is, where it goes, and how fast (units per second).
#[derive(Clone, Copy)]
struct Move<T> {
    position: T,
    goal: T,
    speed: f32,
}

struct LinearFilter<T: Linear> {
    goal: In<T>,
    time: In<f32>,
    position: Out<T>,
    state: Vec<Move<T>>,
}

impl<T: Linear> Node for LinearFilter<T> {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let (goal, time) = (cx.get(self.goal)?, cx.get(self.time)?);
        let n = slice_count([goal.len(), time.len()]);
        let dt = cx.clock.delta as f32;
        let mut moving = false;
        for i in 0..n {
            let (g, t) = (
                usable(*wrapped(goal, i), self.state.get(i).map(|m| m.position)),
                *wrapped(time, i),
            );
            if i >= self.state.len() {
                self.state.push(Move {
                    position: g,
                    goal: g,
                    speed: 0.0,
                });
            }
            let m = &mut self.state[i];
            if m.goal != g {
                m.goal = g;
                m.speed = if t > 0.0 {
                    (g - m.position).length() / t
                } else {
                    f32::INFINITY
                };
                // The frame the goal changes on starts the move: it takes no time yet.
                moving = true;
                continue;
            }
            let left = (m.goal - m.position).length();
            let step = m.speed * dt;
            // Arrived (a NaN step counts as arrived, so nothing non-finite lingers).
            if step.partial_cmp(&left) != Some(std::cmp::Ordering::Less) {
                m.position = m.goal;
            } else {
                m.position = m.position + (m.goal - m.position) * (step / left);
                moving = true;
            }
        }
        self.state.truncate(n);
        if moving {
            cx.reevaluate_next_frame();
        }
        cx.put(
            self.position,
            self.state.iter().map(|m| m.position).collect(),
        );
        Ok(())
    }
}

fn oscillator<T: Linear>(name: &'static str) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "A damped spring pulling Position towards Goal Position: it overshoots and swings \
         around the goal Frequency times a second, losing amplitude by Damping (0: swings \
         forever, 1: critically damped, no overshoot). Integrated in sub-steps, so it stays \
         stable at any frame rate; it stops (and is reused) once it has come to rest. \
         The 4d variant moves colours too: Color pins link to and from 4d vectors.",
    )
    .stateful()
    .with_pins_node(|p| {
        let goal = p.input("Goal Position", T::ZERO);
        let frequency = p.input("Frequency", 1.0f32);
        let damping = p.input("Damping", 0.2f32);
        let position = p.output::<T>("Position");
        let velocity = p.output::<T>("Velocity");
        move || Oscillator::<T> {
            goal,
            frequency,
            damping,
            position,
            velocity,
            state: Vec::new(),
        }
    })
}

struct Oscillator<T: Linear> {
    goal: In<T>,
    frequency: In<f32>,
    damping: In<f32>,
    position: Out<T>,
    velocity: Out<T>,
    /// Position and velocity per slice.
    state: Vec<(T, T)>,
}

impl<T: Linear> Node for Oscillator<T> {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let (goal, freq, damping) = (
            cx.get(self.goal)?,
            cx.get(self.frequency)?,
            cx.get(self.damping)?,
        );
        let n = slice_count([goal.len(), freq.len(), damping.len()]);
        let dt = cx.clock.delta as f32;
        let mut moving = false;
        for i in 0..n {
            let g = usable(*wrapped(goal, i), self.state.get(i).map(|s| s.0));
            if i >= self.state.len() {
                self.state.push((g, T::ZERO));
            }
            let omega = std::f32::consts::TAU * wrapped(freq, i).max(0.0);
            let zeta = wrapped(damping, i).max(0.0);
            let (mut x, mut v) = self.state[i];
            // Semi-implicit Euler is stable for omega * h < 2; a few sub-steps per radian keep it accurate.
            let steps = ((omega * dt * 8.0).ceil() as usize).clamp(1, 256);
            let h = dt / steps as f32;
            for _ in 0..steps {
                let a = (g - x) * (omega * omega) - v * (2.0 * zeta * omega);
                v = v + a * h;
                x = x + v * h;
            }
            let blown_up = !(x.length().is_finite() && v.length().is_finite()) || omega == 0.0;
            let at_rest = settled(x, g) && v.length() <= 1e-4 * (1.0 + g.length());
            if blown_up || at_rest {
                (x, v) = (g, T::ZERO);
            } else {
                moving = true;
            }
            self.state[i] = (x, v);
        }
        self.state.truncate(n);
        if moving {
            cx.reevaluate_next_frame();
        }
        cx.put(self.position, self.state.iter().map(|s| s.0).collect());
        cx.put(self.velocity, self.state.iter().map(|s| s.1).collect());
        Ok(())
    }
}

struct Decay {
    input: In<f32>,
    attack: In<f32>,
    decay: In<f32>,
    output: Out<f32>,
    state: Vec<f32>,
}

impl Node for Decay {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let (input, attack, decay) = (
            cx.get(self.input)?,
            cx.get(self.attack)?,
            cx.get(self.decay)?,
        );
        let n = slice_count([input.len(), attack.len(), decay.len()]);
        let dt = cx.clock.delta;
        let mut moving = false;
        for i in 0..n {
            let x = usable(*wrapped(input, i), self.state.get(i).copied());
            if i >= self.state.len() {
                self.state.push(x);
            }
            let out = &mut self.state[i];
            let time = if x > *out {
                wrapped(attack, i)
            } else {
                wrapped(decay, i)
            };
            *out += (x - *out) * exp_step(*time, dt);
            if settled(*out, x) {
                *out = x;
            } else {
                moving = true;
            }
        }
        self.state.truncate(n);
        if moving {
            cx.reevaluate_next_frame();
        }
        cx.put(self.output, self.state.clone());
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use spreadlight_graph::{NodeRun, Spread};

    use crate::testing::{Harness, assert_close, floats};

    /// Frames until the node stops running, and the outputs seen on the way.
    fn run_until_reused(h: &mut Harness, pin: &str, limit: usize) -> Vec<f32> {
        let mut seen = Vec::new();
        for _ in 0..limit {
            if h.step() == NodeRun::Reused {
                return seen;
            }
            seen.push(h.out::<f32>(pin)[0]);
        }
        panic!("still moving after {limit} frames: {seen:?}");
    }

    #[test]
    fn damper_reaches_one_percent_in_filter_time_and_then_rests() {
        let mut h = Harness::new("Damper (Animation)");
        h.set("Filter Time", floats(&[0.5]));
        assert_eq!(h.next::<f32>("Position"), [0.0]);
        h.set("Goal Position", floats(&[1.0]));
        let seen = run_until_reused(&mut h, "Position", 600);
        // 0.5 s at 60 fps is 30 frames: within 1% there, not before.
        assert!((seen[29] - 0.99).abs() < 1e-3, "{}", seen[29]);
        assert!(seen[28] < 0.99);
        assert!(seen.windows(2).all(|w| w[0] <= w[1]), "monotonic");
        assert_eq!(*seen.last().expect("frames"), 1.0);
    }

    #[test]
    fn linear_filter_arrives_on_time_at_constant_speed() {
        let mut h = Harness::new("LinearFilter (3d)");
        h.set("Filter Time", floats(&[0.1]));
        h.step();
        h.set(
            "Goal Position",
            Spread::Vec3(vec![Vec3::new(6.0, 0.0, 0.0)]),
        );
        let mut xs = Vec::new();
        while h.step() != NodeRun::Reused {
            xs.push(h.out::<Vec3>("Position")[0].x);
            assert!(xs.len() < 100);
        }
        // The goal frame, then six steps of 1 (6 units in 0.1 s at 60 fps); arrived, it rests.
        assert_close(&xs, &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0], 1e-4);
    }

    /// A colour animates through the 4d variant: Color links to Vector 4d and back.
    #[test]
    fn colours_move_through_the_4d_variant() {
        use spreadlight_graph::{Color, FrameClock, NodeDoc, NodeId, Patch, Runtime};
        let mut p = Patch::default();
        p.add(
            NodeDoc::new(1, "IOBox (Color)").with("Input", vec![Color::rgba(1.0, 0.5, 0.0, 1.0)]),
        );
        p.add(NodeDoc::new(2, "Damper (4d)").with("Filter Time", vec![0.0f32]));
        p.add(NodeDoc::new(3, "SetAlpha (Color)"));
        p.add(NodeDoc::new(4, "Probe"));
        p.link(1, "Output", 2, "Goal Position");
        p.link(2, "Position", 3, "Input");
        p.link(3, "Output", 4, "Input");
        let mut rt = Runtime::new(crate::registry());
        assert!(rt.load(&p).is_empty(), "{:?}", rt.problems());
        rt.evaluate(FrameClock::fixed(0, 60.0));
        let out = rt.output(NodeId(3), "Output").expect("colour");
        assert_eq!(**out, Spread::Color(vec![Color::rgba(1.0, 0.5, 0.0, 1.0)]));
    }

    #[test]
    fn oscillator_overshoots_and_settles() {
        let mut h = Harness::new("Oscillator (Animation)");
        h.set("Frequency", floats(&[2.0]))
            .set("Damping", floats(&[0.3]));
        h.step();
        h.set("Goal Position", floats(&[1.0]));
        let seen = run_until_reused(&mut h, "Position", 2000);
        let peak = seen.iter().copied().fold(f32::MIN, f32::max);
        assert!(peak > 1.2 && peak < 1.6, "overshoot {peak}");
        assert_eq!(*seen.last().expect("frames"), 1.0);
        // Critically damped: no overshoot.
        let mut h = Harness::new("Oscillator (Animation)");
        h.set("Damping", floats(&[1.0]));
        h.step();
        h.set("Goal Position", floats(&[1.0]));
        let seen = run_until_reused(&mut h, "Position", 2000);
        assert!(seen.iter().all(|&x| x <= 1.0 + 1e-4), "{seen:?}");
    }

    #[test]
    fn a_non_finite_goal_holds_the_filters_where_they_are() {
        use spreadlight_graph::{FrameClock, NodeDoc, NodeId, Patch, Runtime};
        for (name, goal, out) in [
            ("Damper (Animation)", "Goal Position", "Position"),
            ("LinearFilter (Animation)", "Goal Position", "Position"),
            ("Oscillator (Animation)", "Goal Position", "Position"),
            ("Decay (Animation)", "Input", "Output"),
        ] {
            // Multiply (1e30 x Input) overflows to infinity for large inputs: a
            // non-finite value can only arrive over a link.
            let patch_with = |x: f32| {
                let mut p = Patch::default();
                p.add(
                    NodeDoc::new(1, "Multiply (Value)")
                        .with("Input 1", vec![x])
                        .with("Input 2", vec![1e30f32]),
                );
                p.add(NodeDoc::new(2, name));
                p.add(NodeDoc::new(3, "Probe"));
                p.link(1, "Output", 2, goal);
                p.link(2, out, 3, "Input");
                p
            };
            let mut rt = Runtime::new(crate::registry());
            let mut frame = 0;
            let mut run = |rt: &mut Runtime, x: f32, frames: u64| -> f32 {
                assert!(rt.load(&patch_with(x)).is_empty());
                for _ in 0..frames {
                    rt.evaluate(FrameClock::fixed(frame, 60.0));
                    frame += 1;
                }
                let Some(Spread::Float(v)) = rt.output(NodeId(2), out).map(|s| (**s).clone())
                else {
                    panic!("{name} outputs values")
                };
                v[0]
            };
            assert_eq!(run(&mut rt, 2e-30, 1), 2.0, "{name}");
            assert_eq!(run(&mut rt, 1e30, 3), 2.0, "{name} holds on infinity");
            assert_eq!(run(&mut rt, 3e-30, 600), 3.0, "{name} recovers");
        }
    }

    #[test]
    fn decay_attacks_at_once_and_releases_slowly() {
        let mut h = Harness::new("Decay (Animation)");
        h.set("Decay", floats(&[0.5]));
        h.step();
        h.set("Input", floats(&[1.0]));
        assert_eq!(h.next::<f32>("Output"), [1.0]);
        h.set("Input", floats(&[0.0]));
        let seen = run_until_reused(&mut h, "Output", 600);
        assert!((seen[29] - 0.01).abs() < 1e-3, "{}", seen[29]);
        assert_eq!(*seen.last().expect("frames"), 0.0);
    }
}
