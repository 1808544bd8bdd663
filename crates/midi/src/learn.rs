//! MIDI learn: arm a target (a node's controller pin), move a controller,
//! and the target binds to it. The state machine is generic over what a
//! target is, so the editor can name nodes however it likes, and it is fed
//! parsed messages, so it is tested without a device.

use crate::message::Message;

/// A controller a target was bound to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Binding<T> {
    pub target: T,
    /// 1 to 16.
    pub channel: u8,
    pub controller: u8,
}

/// Idle, waiting for a controller on behalf of a target, or holding a
/// binding until it is taken.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Learn<T> {
    #[default]
    Idle,
    Armed(T),
    Bound(Binding<T>),
}

impl<T: Clone + PartialEq> Learn<T> {
    /// Wait for the next controller on behalf of `target` (replacing any
    /// earlier wait or untaken binding).
    pub fn arm(&mut self, target: T) {
        *self = Learn::Armed(target);
    }

    /// Stop waiting (a second press of the learn button).
    pub fn cancel(&mut self) {
        *self = Learn::Idle;
    }

    /// Whether `target` waits for a controller.
    pub fn is_armed(&self, target: &T) -> bool {
        matches!(self, Learn::Armed(t) if t == target)
    }

    /// The target waiting, if any.
    pub fn armed(&self) -> Option<&T> {
        match self {
            Learn::Armed(t) => Some(t),
            _ => None,
        }
    }

    /// Feed an incoming message: the first control change while armed binds.
    /// Notes, clock and transport leave the wait as it is.
    pub fn feed(&mut self, message: &Message) {
        if let (
            Learn::Armed(target),
            Message::ControlChange {
                channel,
                controller,
                ..
            },
        ) = (&*self, message)
        {
            *self = Learn::Bound(Binding {
                target: target.clone(),
                channel: *channel,
                controller: *controller,
            });
        }
    }

    /// The binding made, once: the state returns to idle.
    pub fn take(&mut self) -> Option<Binding<T>> {
        match std::mem::take(self) {
            Learn::Bound(b) => Some(b),
            other => {
                *self = other;
                None
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::message::parse;

    fn feed(learn: &mut Learn<u32>, bytes: &[u8]) {
        learn.feed(&parse(bytes).expect("a message"));
    }

    #[test]
    fn the_next_controller_after_arming_binds_once() {
        let mut learn = Learn::<u32>::default();
        // Controllers before arming bind nothing.
        feed(&mut learn, &[0xb0, 1, 64]);
        assert_eq!(learn.take(), None);
        learn.arm(7);
        assert!(learn.is_armed(&7) && !learn.is_armed(&8));
        // Notes and clock do not bind.
        feed(&mut learn, &[0x90, 60, 100]);
        feed(&mut learn, &[0xf8]);
        assert_eq!(learn.armed(), Some(&7));
        feed(&mut learn, &[0xb4, 74, 12]);
        // A second controller does not replace the first.
        feed(&mut learn, &[0xb0, 1, 64]);
        assert_eq!(
            learn.take(),
            Some(Binding {
                target: 7,
                channel: 5,
                controller: 74
            })
        );
        assert_eq!(learn.take(), None);
        assert_eq!(learn, Learn::Idle);
    }

    #[test]
    fn arming_again_or_cancelling_replaces_the_wait() {
        let mut learn = Learn::<u32>::default();
        learn.arm(1);
        learn.arm(2);
        feed(&mut learn, &[0xb0, 10, 0]);
        assert_eq!(learn.take().map(|b| b.target), Some(2));
        learn.arm(3);
        learn.cancel();
        feed(&mut learn, &[0xb0, 10, 0]);
        assert_eq!(learn.take(), None);
    }
}
