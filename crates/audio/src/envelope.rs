//! Envelope followers: a level that rises toward the signal's magnitude with
//! one time constant (attack) and falls with another (release), as a
//! compressor's detector does. Attack and release are time constants: a
//! step up reaches 63% (1 - 1/e) of its height after the attack time, a
//! step down falls to 37% after the release time.

/// The per-sample smoothing factor for a time constant of `seconds` at `rate`.
fn coefficient(seconds: f32, rate: u32) -> f32 {
    if seconds <= 0.0 {
        return 0.0;
    }
    (-1.0 / (seconds * rate as f32)).exp()
}

/// Follow the magnitude of `samples` from `start`; returns the final level.
pub fn follow(samples: &[f32], rate: u32, attack: f32, release: f32, start: f32) -> f32 {
    let (a, r) = (coefficient(attack, rate), coefficient(release, rate));
    samples.iter().fold(start, |env, s| {
        let x = s.abs();
        let k = if x > env { a } else { r };
        x + k * (env - x)
    })
}

/// How much of the past an envelope depends on, to within 1%: about five
/// time constants of the slower side (e^-5 < 0.7%).
pub fn memory_seconds(attack: f32, release: f32) -> f32 {
    5.0 * attack.max(release).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attack_and_release_are_time_constants() {
        let rate = 10_000;
        let (attack, release) = (0.01, 0.1);
        // A step up held for the attack time reaches 1 - 1/e.
        let up = follow(&vec![1.0; 100], rate, attack, release, 0.0);
        assert!((up - (1.0 - (-1.0f32).exp())).abs() < 0.002, "{up}");
        // Then silence for the release time leaves 1/e of where it was.
        let full = follow(&vec![1.0; 2000], rate, attack, release, 0.0);
        assert!(full > 0.999, "{full}");
        let down = follow(&vec![0.0; 1000], rate, attack, release, full);
        assert!((down - full * (-1.0f32).exp()).abs() < 0.002, "{down}");
        // Negative samples count by magnitude; zero times follow at once.
        assert_eq!(follow(&[0.2, -0.7], rate, 0.0, 0.0, 0.0), 0.7);
        assert_eq!(memory_seconds(0.01, 0.2), 1.0);
    }
}
