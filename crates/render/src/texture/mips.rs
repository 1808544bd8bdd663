//! Mip chains for 8-bit RGBA images, made on the CPU at upload: each level
//! is a 2x2 box filter of the one above, averaged in linear light for sRGB
//! images (averaging encoded values darkens distant colour textures) and
//! as stored for data (normals, roughness). Odd sizes round down; a level
//! of width or height 1 averages only along the other axis.

/// One level of a chain.
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    pub width: u32,
    pub height: u32,
    pub rgba8: Vec<u8>,
}

/// How many levels a `width` x `height` texture has down to 1x1.
pub fn level_count(width: u32, height: u32) -> u32 {
    32 - width.max(height).max(1).leading_zeros()
}

/// Every level of `rgba8` (`width` x `height`, at least that many bytes
/// used; missing ones read as opaque white), the image itself first.
pub fn chain(width: u32, height: u32, rgba8: &[u8], srgb: bool) -> Vec<Level> {
    let (width, height) = (width.max(1), height.max(1));
    let mut top = rgba8.to_vec();
    top.resize((width * height * 4) as usize, 255);
    let mut levels = vec![Level {
        width,
        height,
        rgba8: top,
    }];
    let to_linear = decode_table(srgb);
    while let Some(last) = levels.last()
        && (last.width > 1 || last.height > 1)
    {
        let next = downsample(last, &to_linear, srgb);
        levels.push(next);
    }
    levels
}

/// Byte to linear value for each of the 256 codes (alpha is always linear).
fn decode_table(srgb: bool) -> [f32; 256] {
    std::array::from_fn(|i| {
        let c = i as f32 / 255.0;
        if !srgb {
            c
        } else if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    })
}

fn encode(linear: f32, srgb: bool) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let c = if !srgb {
        c
    } else if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (c * 255.0 + 0.5) as u8
}

fn downsample(src: &Level, to_linear: &[f32; 256], srgb: bool) -> Level {
    let (w, h) = ((src.width / 2).max(1), (src.height / 2).max(1));
    let mut out = Vec::with_capacity((w * h * 4) as usize);
    // Source texels per output texel along each axis (1 where that axis is already 1).
    let (sx, sy) = (src.width.min(2), src.height.min(2));
    for y in 0..h {
        for x in 0..w {
            let mut sum = [0f32; 4];
            for dy in 0..sy {
                for dx in 0..sx {
                    let i = (((y * sy + dy) * src.width + x * sx + dx) * 4) as usize;
                    for (c, s) in sum.iter_mut().enumerate() {
                        let byte = src.rgba8[i + c];
                        *s += if c == 3 {
                            f32::from(byte) / 255.0
                        } else {
                            to_linear[byte as usize]
                        };
                    }
                }
            }
            let n = (sx * sy) as f32;
            for (c, s) in sum.iter().enumerate() {
                out.push(encode(s / n, srgb && c != 3));
            }
        }
    }
    Level {
        width: w,
        height: h,
        rgba8: out,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chain_goes_down_to_one_texel() {
        assert_eq!(level_count(1, 1), 1);
        assert_eq!(level_count(256, 256), 9);
        assert_eq!(level_count(300, 2), 9);
        let levels = chain(4, 2, &[0; 32], false);
        let sizes: Vec<_> = levels.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, vec![(4, 2), (2, 1), (1, 1)]);
    }

    #[test]
    fn srgb_averages_in_linear_light() {
        // Black and white: the linear mean 0.5 encodes as 188, not 128.
        let pixels = [0, 0, 0, 255, 255, 255, 255, 255];
        let srgb = chain(2, 1, &pixels, true);
        assert_eq!(srgb[1].rgba8, vec![188, 188, 188, 255]);
        let data = chain(2, 1, &pixels, false);
        assert_eq!(data[1].rgba8, vec![128, 128, 128, 255]);
    }
}
