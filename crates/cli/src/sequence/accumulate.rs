//! `--samples K`: offline quality without a real-time budget. Each frame is
//! the average of K sub-frame renders, each at its own instant across the
//! open shutter (motion blur) and with the camera moved by its own
//! sub-pixel offset (anti-aliasing). The accuracy references
//! (`spreadlight accuracy post`) average their sub-frames the same way.

use glam::Vec2;
use spreadlight_render::camera::halton;
use spreadlight_render::readback::ImageF32;

/// The instant of sub-frame `k` of `n`, as a fraction of a frame from the
/// frame's own time: evenly spread over a shutter open for `open` of a
/// frame, centred on the frame (stratified, so the average converges fast).
pub fn shutter_offset(k: u32, n: u32, open: f64) -> f64 {
    if n <= 1 {
        return 0.0;
    }
    ((f64::from(k) + 0.5) / f64::from(n) - 0.5) * open
}

/// The sub-pixel offset of sub-frame `k` of `n`, in pixels within
/// ±0.5: Halton (2, 3), which covers the pixel evenly for any `n`. One
/// sample stays on the pixel centre.
pub fn pixel_offset(k: u32, n: u32) -> Vec2 {
    if n <= 1 {
        return Vec2::ZERO;
    }
    Vec2::new(halton(k + 1, 2) - 0.5, halton(k + 1, 3) - 0.5)
}

/// The running average of images, as they come (in f64, so 256 sub-frames lose nothing).
pub struct Average {
    sum: Vec<[f64; 4]>,
    n: u32,
}

impl Average {
    pub fn new(len: usize) -> Self {
        Average {
            sum: vec![[0.0; 4]; len],
            n: 0,
        }
    }

    pub fn add(&mut self, image: &ImageF32) {
        for (s, p) in self.sum.iter_mut().zip(&image.pixels) {
            for c in 0..4 {
                s[c] += f64::from(p[c]);
            }
        }
        self.n += 1;
    }

    /// `image`, `factor` x `factor` larger than the average, box-downsampled into it
    /// (`factor`² samples a pixel, counted as one image).
    pub fn add_downsampled(&mut self, image: &ImageF32, factor: u32) {
        let small_width = image.width / factor;
        for (i, p) in image.pixels.iter().enumerate() {
            let (x, y) = (
                i as u32 % image.width / factor,
                i as u32 / image.width / factor,
            );
            if let Some(s) = self.sum.get_mut((y * small_width + x) as usize) {
                for c in 0..4 {
                    s[c] += f64::from(p[c]) / f64::from(factor * factor);
                }
            }
        }
        self.n += 1;
    }

    pub fn image(&self, size: (u32, u32)) -> ImageF32 {
        let n = f64::from(self.n.max(1));
        ImageF32 {
            width: size.0,
            height: size.1,
            pixels: self.sum.iter().map(|s| s.map(|v| (v / n) as f32)).collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sub_frames_spread_evenly_and_centred() {
        let offsets: Vec<f64> = (0..4).map(|k| shutter_offset(k, 4, 0.5)).collect();
        assert_eq!(offsets, [-0.1875, -0.0625, 0.0625, 0.1875]);
        assert_eq!(shutter_offset(0, 1, 0.5), 0.0);
        let jitter: Vec<Vec2> = (0..16).map(|k| pixel_offset(k, 16)).collect();
        assert!(jitter.iter().all(|j| j.abs().max_element() <= 0.5));
        let mean = jitter.iter().copied().sum::<Vec2>() / 16.0;
        assert!(mean.length() < 0.05, "{mean}");
        assert_eq!(pixel_offset(0, 1), Vec2::ZERO);
    }

    #[test]
    fn averages_and_downsamples() {
        let image = |v: f32, w, h| ImageF32 {
            width: w,
            height: h,
            pixels: vec![[v; 4]; (w * h) as usize],
        };
        let mut a = Average::new(2);
        a.add(&image(1.0, 2, 1));
        a.add(&image(3.0, 2, 1));
        assert_eq!(a.image((2, 1)).pixels, [[2.0; 4]; 2]);
        let mut d = Average::new(1);
        let mut big = image(0.0, 2, 2);
        big.pixels[0] = [4.0; 4];
        d.add_downsampled(&big, 2);
        assert_eq!(d.image((1, 1)).pixels, [[1.0; 4]]);
    }
}
