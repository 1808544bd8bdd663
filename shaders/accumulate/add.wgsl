// Accumulator (crates/render/src/accumulate/mod.rs): adds one sub-frame of
// `spreadlight render --samples` into a sum of 32-bit floats on the GPU, so a
// frame of N sub-frames is read back once. The texels arrive as a readback
// copies them (rows of `params.size.z` words) and are decoded here exactly
// as the CPU decodes a readback (readback.rs): halves by their bits, 8-bit
// values through the CPU's own table. So the sum is the CPU's f32 sum of
// the same images, in the same order: float additions are correctly rounded.

struct Params {
    // x: width, y: height, z: 32-bit words per row of `texels`, w: the format (FORMAT_*)
    size: vec4<u32>,
}

const FORMAT_RGBA16F: u32 = 0u;
const FORMAT_RGBA32F: u32 = 1u;
const FORMAT_RGBA8_SRGB: u32 = 2u;
const FORMAT_RGBA8: u32 = 3u;
// Depth32Float and R32Float: one float, read as grey.
const FORMAT_R32F: u32 = 4u;
// Rg32Uint (ids): as floats in R and G.
const FORMAT_RG32U: u32 = 5u;

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> texels: array<u32>;
// 512 floats: an 8-bit value's linear value from sRGB (0..255), then as unorm (256..511).
@group(0) @binding(2) var<storage, read> byte_values: array<f32>;
@group(0) @binding(3) var<storage, read_write> sum: array<vec4<f32>>;

// A half's value from its bits, exactly (no driver conversion that might
// flush subnormals).
fn half_value(bits: u32) -> f32 {
    let sign = (bits & 0x8000u) << 16u;
    let exponent = (bits >> 10u) & 0x1fu;
    let mantissa = bits & 0x3ffu;
    if exponent == 0u {
        // Zero or subnormal: mantissa x 2^-24, exact in f32.
        let magnitude = f32(mantissa) * bitcast<f32>(0x33800000u);
        return select(magnitude, -magnitude, sign != 0u);
    }
    if exponent == 31u {
        return bitcast<f32>(sign | 0x7f800000u | (mantissa << 13u));
    }
    return bitcast<f32>(sign | ((exponent + 112u) << 23u) | (mantissa << 13u));
}

fn halves(word: u32) -> vec2<f32> {
    return vec2<f32>(half_value(word & 0xffffu), half_value(word >> 16u));
}

fn texel(x: u32, y: u32) -> vec4<f32> {
    let row = y * params.size.z;
    switch params.size.w {
        case FORMAT_RGBA16F: {
            let i = row + x * 2u;
            return vec4<f32>(halves(texels[i]), halves(texels[i + 1u]));
        }
        case FORMAT_RGBA32F: {
            let i = row + x * 4u;
            return bitcast<vec4<f32>>(vec4<u32>(texels[i], texels[i + 1u], texels[i + 2u], texels[i + 3u]));
        }
        case FORMAT_RGBA8_SRGB, FORMAT_RGBA8: {
            let word = texels[row + x];
            let colour = select(256u, 0u, params.size.w == FORMAT_RGBA8_SRGB);
            return vec4<f32>(
                byte_values[colour + (word & 0xffu)],
                byte_values[colour + ((word >> 8u) & 0xffu)],
                byte_values[colour + ((word >> 16u) & 0xffu)],
                // Alpha is never sRGB-encoded.
                byte_values[256u + (word >> 24u)],
            );
        }
        case FORMAT_R32F: {
            let v = bitcast<f32>(texels[row + x]);
            return vec4<f32>(v, v, v, 1.0);
        }
        case FORMAT_RG32U: {
            let i = row + x * 2u;
            return vec4<f32>(f32(texels[i]), f32(texels[i + 1u]), 0.0, 1.0);
        }
        default: {
            return vec4<f32>(0.0);
        }
    }
}

@compute @workgroup_size(8, 8)
fn add(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= params.size.x || id.y >= params.size.y) {
        return;
    }
    let i = id.y * params.size.x + id.x;
    sum[i] = sum[i] + texel(id.x, id.y);
}
