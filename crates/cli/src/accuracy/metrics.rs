//! How far an approximation is from its reference: the numbers every
//! `spreadlight accuracy` table reports. RMSE on linear values (what the
//! effect computes), and SSIM (the image-compare crate's mean SSIM over 8x8
//! windows) on 8-bit sRGB-encoded images, as a perceptual check: an error
//! that RMSE averages away, such as noise or a lost edge, lowers SSIM.

/// One channel of values to compare, and which pixels count (the rest are
/// held equal to the reference, so they neither add error nor break SSIM's
/// windows).
pub struct Plane<'a> {
    pub width: u32,
    pub height: u32,
    pub values: &'a [f32],
    pub mask: Option<&'a [bool]>,
}

impl<'a> Plane<'a> {
    /// Each channel as a plane of `size`, counting the pixels of `mask`
    /// (every pixel with none).
    pub fn channels(
        channels: &'a [Vec<f32>],
        mask: Option<&'a [bool]>,
        size: (u32, u32),
    ) -> Vec<Self> {
        channels
            .iter()
            .map(|values| Plane {
                width: size.0,
                height: size.1,
                values,
                mask,
            })
            .collect()
    }
}

/// RMSE and SSIM of `approx` against `truth`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Error {
    pub rmse: f64,
    pub ssim: f64,
}

impl Error {
    /// Per-channel planes of the same size; the errors are averaged (RMSE as
    /// the root of the mean squared error over all channels, SSIM as the lowest channel's).
    pub fn of(approx: &[Plane<'_>], truth: &[Plane<'_>]) -> Error {
        assert_eq!(
            approx.len(),
            truth.len(),
            "as many approximate planes as reference planes"
        );
        let mut sum = 0.0;
        let mut n = 0usize;
        let mut ssim = 1.0f64;
        for (a, t) in approx.iter().zip(truth) {
            assert_eq!(
                (a.width, a.height),
                (t.width, t.height),
                "planes of one size"
            );
            let counted = |i: usize| a.mask.is_none_or(|m| m[i]) && t.mask.is_none_or(|m| m[i]);
            for (i, (x, y)) in a.values.iter().zip(t.values).enumerate() {
                if counted(i) {
                    let e = f64::from(finite(*x) - finite(*y));
                    sum += e * e;
                    n += 1;
                }
            }
            let to_gray = |p: &Plane<'_>, own: bool| {
                image::GrayImage::from_fn(p.width, p.height, |x, y| {
                    let i = (y * p.width + x) as usize;
                    let v = if own && counted(i) {
                        a.values[i]
                    } else {
                        t.values[i]
                    };
                    image::Luma([encode(v)])
                })
            };
            let score = image_compare::gray_similarity_structure(
                &image_compare::Algorithm::MSSIMSimple,
                &to_gray(a, true),
                &to_gray(t, false),
            )
            .map(|s| s.score)
            .unwrap_or(0.0);
            ssim = ssim.min(score);
        }
        Error {
            rmse: (sum / n.max(1) as f64).sqrt(),
            ssim,
        }
    }
}

fn finite(v: f32) -> f32 {
    if v.is_finite() { v } else { 0.0 }
}

/// Linear 0..1 to 8-bit sRGB, what a viewer would see.
fn encode(v: f32) -> u8 {
    let v = finite(v).clamp(0.0, 1.0);
    let s = if v <= 0.003_130_8 {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane(values: &[f32], width: u32) -> Plane<'_> {
        Plane {
            width,
            height: values.len() as u32 / width,
            values,
            mask: None,
        }
    }

    #[test]
    fn identical_planes_have_no_error() {
        let v: Vec<f32> = (0..256).map(|i| (i % 16) as f32 / 16.0).collect();
        let e = Error::of(&[plane(&v, 16)], &[plane(&v, 16)]);
        assert_eq!(e.rmse, 0.0);
        assert!((e.ssim - 1.0).abs() < 1e-9, "{e:?}");
    }

    #[test]
    fn rmse_is_the_root_mean_square_and_noise_lowers_ssim() {
        let truth = vec![0.5f32; 256];
        let noisy: Vec<f32> = (0..256)
            .map(|i| if i % 2 == 0 { 0.6 } else { 0.4 })
            .collect();
        let e = Error::of(&[plane(&noisy, 16)], &[plane(&truth, 16)]);
        assert!((e.rmse - 0.1).abs() < 1e-6, "{e:?}");
        assert!(e.ssim < 0.9, "{e:?}");
    }

    #[test]
    fn masked_pixels_count_for_nothing() {
        let truth = vec![0.5f32; 64];
        let mut approx = truth.clone();
        approx[0] = 1.0;
        let mut mask = vec![true; 64];
        mask[0] = false;
        let a = Plane {
            mask: Some(&mask),
            ..plane(&approx, 8)
        };
        let e = Error::of(&[a], &[plane(&truth, 8)]);
        assert_eq!(e.rmse, 0.0);
        assert!((e.ssim - 1.0).abs() < 1e-9);
    }

    #[test]
    fn nan_counts_as_black_not_as_nan() {
        let truth = vec![0.5f32; 64];
        let mut approx = truth.clone();
        approx[3] = f32::NAN;
        let e = Error::of(&[plane(&approx, 8)], &[plane(&truth, 8)]);
        assert!(e.rmse.is_finite() && e.rmse > 0.0);
        assert!(e.ssim.is_finite());
    }
}
