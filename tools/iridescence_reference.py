#!/usr/bin/env python3
"""The thin-film Fresnel of KHR_materials_iridescence, run by hand: a line
by line transcription of the Khronos glTF Sample Viewer's GLSL
(KhronosGroup/glTF-Sample-Renderer, source/Renderer/shaders/iridescence.glsl:
evalSensitivity and evalIridescence, after Belcour & Barla 2017), in double
precision and written without looking at the Rust port
(crates/reference/src/iridescence.rs). Its output is pasted into that
module's tests, which check the Rust port against it.

    python3 tools/iridescence_reference.py
"""

import math

# GLSL's mat3 is column-major: these are the columns of XYZ_TO_REC709.
XYZ_TO_REC709_COLUMNS = (
    (3.2404542, -0.9692660, 0.0556434),
    (-1.5371385, 1.8760108, -0.2040259),
    (-0.4985314, 0.0415560, 1.0572252),
)


def sq(x):
    return x * x


def f_schlick(f0, cos_theta):
    # F_Schlick(f0, f90 = 1, VdotH) of the sample viewer's brdf.glsl
    return f0 + (1.0 - f0) * (1.0 - cos_theta) ** 5


def ior_to_fresnel0(transmitted, incident):
    return sq((transmitted - incident) / (transmitted + incident))


def fresnel0_to_ior(f0):
    s = math.sqrt(f0)
    return (1.0 + s) / (1.0 - s)


def eval_sensitivity(opd, shift):
    phase = 2.0 * math.pi * opd * 1.0e-9
    val = (5.4856e-13, 4.4201e-13, 5.2481e-13)
    pos = (1.6810e06, 1.7953e06, 2.2084e06)
    var = (4.3278e09, 9.3046e09, 6.6121e09)
    xyz = [
        val[i] * math.sqrt(2.0 * math.pi * var[i]) * math.cos(pos[i] * phase + shift[i])
        * math.exp(-sq(phase) * var[i])
        for i in range(3)
    ]
    xyz[0] += (9.7470e-14 * math.sqrt(2.0 * math.pi * 4.5282e09)
               * math.cos(2.2399e06 * phase + shift[0]) * math.exp(-4.5282e09 * sq(phase)))
    xyz = [x / 1.0685e-7 for x in xyz]
    c = XYZ_TO_REC709_COLUMNS
    return [sum(c[j][i] * xyz[j] for j in range(3)) for i in range(3)]


def smoothstep(e0, e1, x):
    t = min(max((x - e0) / (e1 - e0), 0.0), 1.0)
    return t * t * (3.0 - 2.0 * t)


def eval_iridescence(outside_ior, eta2, cos_theta1, thickness, base_f0):
    iridescence_ior = outside_ior + (eta2 - outside_ior) * smoothstep(0.0, 0.03, thickness)
    sin_theta2_sq = sq(outside_ior / iridescence_ior) * (1.0 - sq(cos_theta1))
    cos_theta2_sq = 1.0 - sin_theta2_sq
    if cos_theta2_sq < 0.0:
        return [1.0, 1.0, 1.0]
    cos_theta2 = math.sqrt(cos_theta2_sq)
    r0 = ior_to_fresnel0(iridescence_ior, outside_ior)
    r12 = f_schlick(r0, cos_theta1)
    t121 = 1.0 - r12
    phi12 = math.pi if iridescence_ior < outside_ior else 0.0
    phi21 = math.pi - phi12
    base_ior = [fresnel0_to_ior(min(max(f, 0.0), 0.9999)) for f in base_f0]
    r1 = [ior_to_fresnel0(b, iridescence_ior) for b in base_ior]
    r23 = [f_schlick(r, cos_theta2) for r in r1]
    phi23 = [math.pi if b < iridescence_ior else 0.0 for b in base_ior]
    opd = 2.0 * iridescence_ior * thickness * cos_theta2
    phi = [phi21 + p for p in phi23]
    r123 = [min(max(r12 * r, 1e-5), 0.9999) for r in r23]
    r123_root = [math.sqrt(r) for r in r123]
    rs = [sq(t121) * r23[i] / (1.0 - r123[i]) for i in range(3)]
    i_out = [r12 + rs[i] for i in range(3)]
    cm = [rs[i] - t121 for i in range(3)]
    for m in (1, 2):
        cm = [cm[i] * r123_root[i] for i in range(3)]
        sm = [2.0 * s for s in eval_sensitivity(m * opd, [m * p for p in phi])]
        i_out = [i_out[i] + cm[i] * sm[i] for i in range(3)]
    return [max(x, 0.0) for x in i_out]


if __name__ == "__main__":
    # (film ior, cos theta1, thickness nm, base f0): a soap film over water
    # and over glass, an oil film over a metal, grazing, thin and total
    # internal reflection (film ior below the outside's is not possible
    # here: outside is air, 1).
    cases = [
        (1.3, 1.0, 400.0, (0.04, 0.04, 0.04)),
        (1.3, 0.5, 400.0, (0.04, 0.04, 0.04)),
        (1.3, 1.0, 250.0, (0.04, 0.04, 0.04)),
        (1.33, 0.8, 100.0, (0.02, 0.02, 0.02)),
        (1.5, 0.3, 600.0, (0.9, 0.6, 0.3)),
        (1.3, 0.05, 400.0, (0.04, 0.04, 0.04)),
        (1.3, 1.0, 10.0, (0.04, 0.04, 0.04)),
        (1.8, 0.7, 1200.0, (0.04, 0.5, 0.99)),
    ]
    for ior, cos1, d, f0 in cases:
        r = eval_iridescence(1.0, ior, cos1, d, f0)
        print(f"ior {ior}, cos {cos1}, thickness {d}, f0 {list(f0)} -> [{r[0]:.7f}, {r[1]:.7f}, {r[2]:.7f}]")
