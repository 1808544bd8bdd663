#!/usr/bin/env python3
"""Writes the help patches in patches/help/ (one per node family; F1 in the
editor and `spreadlight nodes --help NAME` open them; the table of which
patch covers which node type is crates/nodes/src/help.rs).

Each patch is laid out here in data-flow columns, with room measured from
the node's pins as docs/nodes.md lists them (generous: ~250 px between
columns, ~120 px between rows, at the editor's 3 canvas px per patch unit),
and starts with an `IOBox (String)` whose slices explain it (the patch
format has no comments yet). Run from the repository root, then
`spreadlight fmt patches/help/*.ron` to write them in canonical form. The
patches are the source of truth once written: edit them in the editor.
"""
import re, os, struct

SCALE = 3.0          # canvas px per patch unit (crates/editor/src/canvas/sync.rs)
COL_GAP = 260.0      # px between columns
ROW_GAP = 130.0      # px between rows
ROW_PX = 20.0        # a pin row
HEADER_PX = 30.0
CHAR_PX = 7.5

DOC = open("docs/nodes.md").read()

def pins(ty):
    m = re.search(r"^### " + re.escape(ty) + r"\n(.*?)(?=^### |^## )", DOC, re.S | re.M)
    if not m:
        raise SystemExit(f"unknown node type {ty}")
    body = m.group(1)
    ins = [l.split("|")[1].strip() for l in body.splitlines()
           if l.startswith("| ") and not l.startswith("| input")]
    om = re.search(r"^Outputs: (.*)\.$", body, re.M)
    outs = [o.split(" (")[0] for o in re.split(r", (?![^()]*\))", om.group(1))] if om else []
    return ins, outs

def F(*v): return "Float([%s])" % ", ".join(repr(float(x)) for x in v)
def I(*v): return "Int([%s])" % ", ".join(str(int(x)) for x in v)
def B(v): return "Bool([%s])" % ("true" if v else "false")
def S(*v): return "String([%s])" % ", ".join('"%s"' % x for x in v)
def E(v): return 'Enum(["%s"])' % v
def V2(x, y): return "Vec2([(%r, %r)])" % (float(x), float(y))
def V3(x, y, z): return "Vec3([(%r, %r, %r)])" % (float(x), float(y), float(z))
def C(r, g, b, a=1.0): return "Color([(r: %r, g: %r, b: %r, a: %r)])" % (float(r), float(g), float(b), float(a))

class Patch:
    def __init__(self, file, lines):
        self.file, self.nodes, self.links = file, [], []
        self.note = self.n("IOBox (String)", Input=S(*lines))
        self.lines = lines

    def n(self, ty, **values):
        pins(ty)
        self.nodes.append({"id": len(self.nodes) + 1, "type": ty,
                           "values": {k.replace("_", " "): v for k, v in values.items()}})
        return len(self.nodes)

    def l(self, a, out, b, inp):
        ains, aouts = pins(self.nodes[a - 1]["type"])
        bins, _ = pins(self.nodes[b - 1]["type"])
        assert out in aouts, (self.nodes[a - 1]["type"], out, aouts)
        assert inp in bins, (self.nodes[b - 1]["type"], inp, bins)
        self.links.append((a, out, b, inp))

    def size(self, node):
        ins, outs = pins(node["type"])
        if node["type"] == "IOBox (String)":
            w = max(len(s) for s in self.lines) * CHAR_PX + 60
            return w, HEADER_PX + ROW_PX * (len(self.lines) + 2)
        rows = max(len(ins), len(outs))
        wi = max([len(p) for p in ins] or [0])
        wo = max([len(p) for p in outs] or [0])
        w = max(len(node["type"]) * CHAR_PX + 20, (wi + wo) * CHAR_PX + 150)
        return w, HEADER_PX + ROW_PX * rows

    def layout(self):
        depth = {n["id"]: 0 for n in self.nodes}
        for _ in self.nodes:
            for a, _, b, _ in self.links:
                depth[b] = max(depth[b], depth[a] + 1)
        cols = {}
        for n in self.nodes[1:]:
            cols.setdefault(depth[n["id"]], []).append(n)
        _, note_h = self.size(self.nodes[0])
        top = note_h + ROW_GAP
        self.nodes[0]["pos"] = (0.0, 0.0)
        x = 0.0
        for c in sorted(cols):
            y = top
            width = 0.0
            for n in cols[c]:
                w, h = self.size(n)
                n["pos"] = (round(x / SCALE), round(y / SCALE))
                y += h + ROW_GAP
                width = max(width, w)
            x += width + COL_GAP

    def write(self):
        self.layout()
        out = ["(", "    version: 1,", "    nodes: ["]
        for n in self.nodes:
            out.append("        (")
            out.append(f'            id: {n["id"]},')
            out.append(f'            type: "{n["type"]}",')
            out.append("            pos: (%r, %r)," % (float(n["pos"][0]), float(n["pos"][1])))
            if n["values"]:
                out.append("            values: {")
                for k in sorted(n["values"]):
                    out.append(f'                "{k}": {n["values"][k]},')
                out.append("            },")
            out.append("        ),")
        out.append("    ],")
        out.append("    links: [")
        for a, o, b, i in self.links:
            out.append(f'        (\n            from: ({a}, "{o}"),\n            to: ({b}, "{i}"),\n        ),')
        out.append("    ],")
        out.append(")")
        with open(os.path.join("patches/help", self.file), "w") as f:
            f.write("\n".join(out) + "\n")

# ----- shared pieces -----

def scene(p, glass=False):
    """A floor and a ball on it, seen by a turning camera: the G-buffer."""
    plane = p.n("Plane", Size=V2(12, 12))
    floor = p.n("DeferredBase", Color=C(0.6, 0.6, 0.6), Material_ID=I(0))
    p.l(plane, "Mesh", floor, "Mesh")
    ball = p.n("Sphere", Radius=F(0.8), Sectors=I(32), Stacks=I(16))
    lift = p.n("Translate (Transform)", Y=F(0.8))
    base = p.n("DeferredBase", Color=C(0.9, 0.45, 0.2), Material_ID=I(1))
    p.l(ball, "Mesh", base, "Mesh")
    p.l(lift, "Transform Out", base, "Transform")
    group = p.n("Group (Layer)")
    p.l(floor, "Layer", group, "Layer 1")
    p.l(base, "Layer", group, "Layer 2")
    lfo = p.n("LFO", Period=F(12))
    cam = p.n("Camera", Distance=F(5.0), Pitch=F(0.3), Target=V3(0, 0.6, 0))
    p.l(lfo, "Output", cam, "Yaw")
    mre = p.n("MRE")
    p.l(group, "Layer", mre, "Layer")
    p.l(cam, "View", mre, "View")
    p.l(cam, "Projection", mre, "Projection")
    return {"mre": mre, "cam": cam, "group": group, "base": base, "lfo": lfo}

def sun(p, s, world=None, shadows=None):
    light = p.n("AddLight (Sun)", Direction=V3(-0.4, -1.0, -0.3), Illuminance=F(2.5),
                **({"Shadow_Slice": I(0)} if shadows else {}))
    buf = p.n("SunLightBuffer")
    p.l(light, "Lights", buf, "Lights")
    ct = p.n("CookTorrance")
    p.l(s["mre"], "G-Buffer", ct, "G-Buffer")
    p.l(buf, "Lights", ct, "Lights")
    if world:
        p.l(world, "Material World", ct, "Material World")
    return light, ct

def composite(p, s, diffuse, specular, world=None, **values):
    comp = p.n("CompositeLight", Ambient=C(0.04, 0.045, 0.055), **values)
    p.l(s["mre"], "G-Buffer", comp, "G-Buffer")
    p.l(diffuse[0], diffuse[1], comp, "Diffuse")
    p.l(specular[0], specular[1], comp, "Specular")
    if world:
        p.l(world, "Material World", comp, "Material World")
    return comp

def output(p, tex, name, tonemap=True):
    if tonemap:
        tm = p.n("Tonemap", Operator=E("ACES"))
        p.l(tex, "Texture", tm, "Texture")
        tex = tm
    o = p.n("Output", Name=S(name), Write=B(False))
    p.l(tex, "Texture", o, "Texture")
    return o

# ----- the families -----

def deferred():
    p = Patch("deferred.ron", [
        "Help: the G-buffer (Emeshe's deferred base).",
        "DeferredBase draws a Mesh with a Transform and a Color",
        "into a Layer; Group (Layer) joins layers; MRE renders",
        "them through a Camera's View and Projection into the",
        "G-buffer. GBufferView shows one channel of it: pick",
        "Channel (Normals, Albedo, Depth, Velocity...).",
    ])
    s = scene(p)
    view = p.n("GBufferView", Channel=E("Normals"))
    p.l(s["mre"], "G-Buffer", view, "G-Buffer")
    output(p, view, "normals", tonemap=False)
    return p

def lighting():
    p = Patch("lighting.ron", [
        "Help: lights. AddLight (Sun / Point / Spot) adds lights",
        "to a list; each list's LightBuffer packs it for the GPU;",
        "CookTorrance lights the G-buffer with one buffer, giving",
        "Diffuse and Specular; Group (Texture) adds those up and",
        "CompositeLight combines them with the albedo and Ambient.",
        "Tonemap maps the HDR result for the Output.",
    ])
    s = scene(p)
    sun_light, ct_sun = sun(p, s)
    point = p.n("AddLight (Point)", Position=V3(1.5, 1.2, 1.0), Color=C(0.3, 0.6, 1.0),
                Intensity=F(8), Range=F(6))
    pbuf = p.n("PointLightBuffer")
    p.l(point, "Lights", pbuf, "Lights")
    ct_point = p.n("CookTorrance")
    p.l(s["mre"], "G-Buffer", ct_point, "G-Buffer")
    p.l(pbuf, "Lights", ct_point, "Lights")
    look = p.n("LookAt (Transform)", Position=V3(-2, 4, 2), Target=V3(0, 0.5, 0))
    persp = p.n("Perspective (Transform)", FOV=F(0.15), Far=F(12))
    spot = p.n("AddLight (Spot)", Intensity=F(40), Color=C(1.0, 0.8, 0.5))
    p.l(look, "Transform Out", spot, "View")
    p.l(persp, "Transform Out", spot, "Projection")
    sbuf = p.n("SpotLightBuffer")
    p.l(spot, "Lights", sbuf, "Lights")
    ct_spot = p.n("CookTorrance")
    p.l(s["mre"], "G-Buffer", ct_spot, "G-Buffer")
    p.l(sbuf, "Lights", ct_spot, "Lights")
    dif = p.n("Group (Texture)")
    spec = p.n("Group (Texture)")
    for i, ct in enumerate([ct_sun, ct_point, ct_spot]):
        p.l(ct, "Diffuse", dif, f"Texture {i + 1}")
        p.l(ct, "Specular", spec, f"Texture {i + 1}")
    comp = composite(p, s, (dif, "Texture"), (spec, "Texture"))
    output(p, comp, "lit")
    return p

def shadows():
    p = Patch("shadows.ron", [
        "Help: shadows. A ShadowMap renders the casters (Layer)",
        "from each light whose Shadow Slice is 0 or more, for the",
        "view in the G-Buffer; its Shadows go to that light type's",
        "CookTorrance. Filter: Raw, PCF, PCSS (soft) or VSM.",
        "Sun maps are cascaded (Cascades, Distance).",
    ])
    s = scene(p)
    light, ct = sun(p, s, shadows=True)
    sm = p.n("ShadowMap (Sun)", Resolution=I(256), Cascades=I(2), Distance=F(15), Filter=E("PCSS"))
    p.l(s["group"], "Layer", sm, "Layer")
    p.l(s["mre"], "G-Buffer", sm, "G-Buffer")
    p.l(light, "Lights", sm, "Lights")
    p.l(sm, "Shadows", ct, "Shadows")
    point = p.n("AddLight (Point)", Position=V3(1.5, 2.0, 1.0), Intensity=F(6), Range=F(6),
                Shadow_Slice=I(0))
    pbuf = p.n("PointLightBuffer")
    p.l(point, "Lights", pbuf, "Lights")
    psm = p.n("ShadowMap (Point)", Resolution=I(128))
    p.l(s["group"], "Layer", psm, "Layer")
    p.l(s["mre"], "G-Buffer", psm, "G-Buffer")
    p.l(point, "Lights", psm, "Lights")
    ct_point = p.n("CookTorrance")
    p.l(s["mre"], "G-Buffer", ct_point, "G-Buffer")
    p.l(pbuf, "Lights", ct_point, "Lights")
    p.l(psm, "Shadows", ct_point, "Shadows")
    look = p.n("LookAt (Transform)", Position=V3(-2, 4, 2), Target=V3(0, 0.5, 0))
    persp = p.n("Perspective (Transform)", FOV=F(0.15), Far=F(12))
    spot = p.n("AddLight (Spot)", Intensity=F(40), Shadow_Slice=I(0))
    p.l(look, "Transform Out", spot, "View")
    p.l(persp, "Transform Out", spot, "Projection")
    sbuf = p.n("SpotLightBuffer")
    p.l(spot, "Lights", sbuf, "Lights")
    ssm = p.n("ShadowMap (Spot)", Resolution=I(256))
    p.l(s["group"], "Layer", ssm, "Layer")
    p.l(s["mre"], "G-Buffer", ssm, "G-Buffer")
    p.l(spot, "Lights", ssm, "Lights")
    ct_spot = p.n("CookTorrance")
    p.l(s["mre"], "G-Buffer", ct_spot, "G-Buffer")
    p.l(sbuf, "Lights", ct_spot, "Lights")
    p.l(ssm, "Shadows", ct_spot, "Shadows")
    dif = p.n("Group (Texture)")
    spec = p.n("Group (Texture)")
    for i, c in enumerate([ct, ct_point, ct_spot]):
        p.l(c, "Diffuse", dif, f"Texture {i + 1}")
        p.l(c, "Specular", spec, f"Texture {i + 1}")
    comp = composite(p, s, (dif, "Texture"), (spec, "Texture"))
    output(p, comp, "shadows")
    return p

def materials():
    p = Patch("material.ron", [
        "Help: materials. Feature chains (AddCookTorrance, AddEmission,",
        "AddAmbientOcclusion, AddMatCap; FeatureManager sets any",
        "feature by id) make a material; MaterialManager places it",
        "at a Material ID; MaterialBuffer uploads them as the Material",
        "World that CookTorrance and CompositeLight read. DeferredBase's",
        "Material ID picks one; MaterialByName finds an id by name.",
    ])
    s = scene(p)
    floor = p.n("AddCookTorrance", Roughness=F(0.8))
    floor_ao = p.n("AddAmbientOcclusion", Strength=F(1.0))
    p.l(floor, "Material", floor_ao, "Material")
    ball = p.n("AddCookTorrance", Roughness=F(0.3), Metallic=F(1.0))
    glow = p.n("AddEmission", Color=C(1.0, 0.4, 0.1), Strength=F(0.4))
    p.l(ball, "Material", glow, "Material")
    cap = p.n("AddMatCap", Strength=F(0.5), Mode=E("Add"), MatCap_Texture_ID=I(0))
    p.l(glow, "Material", cap, "Material")
    feature = p.n("FeatureManager", Feature_ID=I(1), Parameters="Vec4([(0.1, 0.2, 0.5, 0.2)])")
    p.l(floor_ao, "Material", feature, "Material")
    m0 = p.n("MaterialManager", Material_ID=I(0))
    p.l(feature, "Material", m0, "Material")
    m1 = p.n("MaterialManager", Material_ID=I(1))
    p.l(m0, "Materials", m1, "Materials")
    p.l(cap, "Material", m1, "Material")
    caps = p.n("FileTexture (Array)", Filenames=S("../assets/matcap-chrome.png"))
    buf = p.n("MaterialBuffer")
    p.l(m1, "Materials", buf, "Materials")
    p.l(caps, "Texture", buf, "Textures")
    byname = p.n("MaterialByName", Names=S("floor", "ball"), Name=S("ball"))
    p.l(m1, "Materials", byname, "Materials")
    p.l(byname, "Material ID", s["base"], "Material ID")
    _, ct = sun(p, s, world=buf)
    comp = composite(p, s, (ct, "Diffuse"), (ct, "Specular"), world=buf)
    output(p, comp, "materials")
    return p

def occlusion():
    p = Patch("occlusion.ron", [
        "Help: screen-space lighting. SSAO and HBAO darken creases",
        "(CompositeLight's AO; HBAO can refine SSAO's AO), SSGI",
        "bounces the lit Diffuse around (GI), and SSSS blurs the",
        "CookTorrance SSS term under the skin of materials with",
        "AddFakeSSS (SSS). All read the G-buffer.",
    ])
    s = scene(p)
    mat = p.n("AddCookTorrance", Roughness=F(0.5))
    sss = p.n("AddFakeSSS", Color=C(1.0, 0.35, 0.15), Strength=F(0.0, 0.6))
    p.l(mat, "Material", sss, "Material")
    buf = p.n("MaterialBuffer")
    p.l(sss, "Material", buf, "Materials")
    _, ct = sun(p, s, world=buf)
    ssao = p.n("SSAO", Radius=F(1.0), Samples=I(6))
    p.l(s["mre"], "G-Buffer", ssao, "G-Buffer")
    hbao = p.n("HBAO", Radius=F(0.3), Directions=I(4))
    p.l(s["mre"], "G-Buffer", hbao, "G-Buffer")
    p.l(ssao, "Texture", hbao, "AO")
    ssgi = p.n("SSGI", Radius=F(1.5))
    p.l(s["mre"], "G-Buffer", ssgi, "G-Buffer")
    p.l(ct, "Diffuse", ssgi, "Texture")
    ssss = p.n("SSSS", Width=F(0.15))
    p.l(s["mre"], "G-Buffer", ssss, "G-Buffer")
    p.l(ct, "SSS", ssss, "Texture")
    p.l(buf, "Material World", ssss, "Material World")
    comp = composite(p, s, (ct, "Diffuse"), (ct, "Specular"), world=buf)
    p.l(hbao, "Texture", comp, "AO")
    p.l(ssgi, "Texture", comp, "GI")
    p.l(ssss, "Texture", comp, "SSS")
    output(p, comp, "occlusion")
    return p

def environment():
    p = Patch("environment.ron", [
        "Help: environment. Environment (Sky) or Environment (File)",
        "(an .hdr/.exr) prefilters a cube map; Reflection reads it per",
        "pixel for materials with AddReflection; SSR traces the lit",
        "image on screen and falls back to it; CompositeLight takes",
        "it as Reflection. Fog and Sky go over the lit image.",
    ])
    s = scene(p)
    mat = p.n("AddCookTorrance", Roughness=F(0.2, 0.3))
    refl = p.n("AddReflection", Strength=F(0.3, 1.0))
    p.l(mat, "Material", refl, "Material")
    buf = p.n("MaterialBuffer")
    p.l(refl, "Material", buf, "Materials")
    _, ct = sun(p, s, world=buf)
    env = p.n("Environment (Sky)", Intensity=F(0.5), Sun_Direction=V3(-0.4, -1.0, -0.3), Cube_Size=I(32), Samples=I(16))
    reflection = p.n("Reflection")
    p.l(s["mre"], "G-Buffer", reflection, "G-Buffer")
    p.l(buf, "Material World", reflection, "Material World")
    p.l(env, "Environment", reflection, "Environment")
    envfile = p.n("Environment (File)", Filename=S("../assets/help-sky.hdr"), Cube_Size=I(16), Samples=I(16))
    reflection2 = p.n("Reflection")
    p.l(s["mre"], "G-Buffer", reflection2, "G-Buffer")
    p.l(buf, "Material World", reflection2, "Material World")
    p.l(envfile, "Environment", reflection2, "Environment")
    lit = composite(p, s, (ct, "Diffuse"), (ct, "Specular"), world=buf)
    ssr = p.n("SSR")
    p.l(s["mre"], "G-Buffer", ssr, "G-Buffer")
    p.l(buf, "Material World", ssr, "Material World")
    p.l(lit, "Texture", ssr, "Lit")
    p.l(reflection, "Specular", ssr, "Fallback")
    comp = composite(p, s, (ct, "Diffuse"), (ct, "Specular"), world=buf)
    p.l(ssr, "Texture", comp, "Reflection")
    fog = p.n("Fog", Color=C(0.6, 0.7, 0.85), Density=F(0.05), Start=F(3))
    p.l(comp, "Texture", fog, "Texture")
    p.l(s["mre"], "G-Buffer", fog, "G-Buffer")
    sky = p.n("Sky", Sun_Direction=V3(-0.4, -1.0, -0.3))
    p.l(fog, "Texture", sky, "Texture")
    p.l(s["mre"], "G-Buffer", sky, "G-Buffer")
    output(p, sky, "environment")
    # The file environment lit on its own: its diffuse as the ambient term.
    comp2 = composite(p, s, (ct, "Diffuse"), (ct, "Specular"), world=buf)
    p.l(reflection2, "Specular", comp2, "Reflection")
    output(p, comp2, "environment-file")
    return p

def post():
    p = Patch("post.ron", [
        "Help: post FX, in the order a frame usually takes them:",
        "Transparency (glass over the lit image), DOF (focused by",
        "Autofocus), MotionBlur, Glare, TAA (with the Camera's",
        "Jitter), Tonemap (exposure from EyeAdaptation), FXAA.",
        "BlurBuiltin is a plain blur (the second Output).",
    ])
    s = scene(p)
    _, ct = sun(p, s)
    comp = composite(p, s, (ct, "Diffuse"), (ct, "Specular"))
    glass = p.n("Sphere", Radius=F(0.5), Sectors=I(24), Stacks=I(12))
    at = p.n("Translate (Transform)", X=F(1.2), Y=F(1.0), Z=F(1.2))
    gbase = p.n("DeferredBase", Color=C(0.6, 0.85, 1.0, 0.35))
    p.l(glass, "Mesh", gbase, "Mesh")
    p.l(at, "Transform Out", gbase, "Transform")
    tr = p.n("Transparency")
    p.l(comp, "Texture", tr, "Texture")
    p.l(s["mre"], "G-Buffer", tr, "G-Buffer")
    p.l(gbase, "Layer", tr, "Layer")
    af = p.n("Autofocus", Point=V2(0.5, 0.55))
    p.l(s["mre"], "G-Buffer", af, "G-Buffer")
    dof = p.n("DOF", **{"F-Stop": F(1.4)}, Focal_Length=F(200), Samples=I(8))
    p.l(tr, "Texture", dof, "Texture")
    p.l(s["mre"], "G-Buffer", dof, "G-Buffer")
    p.l(af, "Focus", dof, "Focus")
    mb = p.n("MotionBlur", Shutter_Angle=F(270))
    p.l(dof, "Texture", mb, "Texture")
    p.l(s["mre"], "G-Buffer", mb, "G-Buffer")
    gl = p.n("Glare", Intensity=F(0.4), Threshold=F(0.8))
    p.l(mb, "Texture", gl, "Texture")
    taa = p.n("TAA")
    p.l(gl, "Texture", taa, "Texture")
    p.l(s["mre"], "G-Buffer", taa, "G-Buffer")
    p.l(s["cam"], "Jitter", taa, "Jitter")
    eye = p.n("EyeAdaptation")
    p.l(taa, "Texture", eye, "Texture")
    tm = p.n("Tonemap", Operator=E("ACES"))
    p.l(taa, "Texture", tm, "Texture")
    p.l(eye, "Luminance", tm, "Eye Adaptation")
    fx = p.n("FXAA")
    p.l(tm, "Texture", fx, "Texture")
    output(p, fx, "post", tonemap=False)
    blur = p.n("BlurBuiltin", Radius=F(3))
    p.l(fx, "Texture", blur, "Texture")
    output(p, blur, "blurred", tonemap=False)
    return p

def values():
    p = Patch("values.ron", [
        "Help: values. LFO ramps 0..1 once per Period (seconds);",
        "Sin and Cos take turns (1 = a full turn); Multiply, Add,",
        "Subtract, Divide do arithmetic slice by slice; Map maps",
        "one range onto another, Clamp keeps within one. IOBox",
        "(Value) holds a value to edit; Probe names what it sees",
        "(hover a pin or wire to read it).",
    ])
    lfo = p.n("LFO", Period=F(4))
    sin = p.n("Sin (Value)")
    p.l(lfo, "Output", sin, "Input")
    gain = p.n("IOBox (Value)", Input=F(10))
    mul = p.n("Multiply (Value)")
    p.l(sin, "Output", mul, "Input 1")
    p.l(gain, "Output", mul, "Input 2")
    add = p.n("Add (Value)", Input_2=F(1))
    p.l(mul, "Output", add, "Input 1")
    probe = p.n("Probe", Name=S("sine"))
    p.l(add, "Output", probe, "Input")
    cos = p.n("Cos (Value)")
    p.l(lfo, "Output", cos, "Input")
    sub = p.n("Subtract (Value)", Input_2=F(0.5))
    p.l(cos, "Output", sub, "Input 1")
    div = p.n("Divide (Value)", Input_2=F(2))
    p.l(sub, "Output", div, "Input 1")
    mp = p.n("Map (Value)", Source_Minimum=F(-0.75), Source_Maximum=F(0.25),
             Destination_Minimum=F(0), Destination_Maximum=F(100))
    p.l(div, "Output", mp, "Input")
    cl = p.n("Clamp (Value)", Minimum=F(10), Maximum=F(90))
    p.l(mp, "Output", cl, "Input")
    probe2 = p.n("Probe", Name=S("cosine"))
    p.l(cl, "Output", probe2, "Input")
    return p

def spreads():
    p = Patch("spreads.ron", [
        "Help: spreads. Every pin carries a list of slices.",
        "LinearSpread spreads Spread Count values over Width around",
        "Input; CircularSpread places them on a circle; RandomSpread",
        "draws them; I counts Start..End. Count, Sum and Mean reduce",
        "a spread; GetSlice picks one, Reverse and Sort reorder.",
    ])
    lin = p.n("LinearSpread", Width=F(2), Spread_Count=I(5))
    cnt = p.n("Count (Spreads)")
    p.l(lin, "Output", cnt, "Input")
    sm = p.n("Sum (Spreads)")
    p.l(lin, "Output", sm, "Input")
    rev = p.n("Reverse (Spreads)")
    p.l(lin, "Output", rev, "Input")
    gs = p.n("GetSlice (Spreads)", Index=I(1))
    p.l(rev, "Output", gs, "Input")
    rnd = p.n("RandomSpread", Spread_Count=I(6), Random_Seed=I(7))
    srt = p.n("Sort (Spreads)")
    p.l(rnd, "Output", srt, "Input")
    mean = p.n("Mean (Spreads)")
    p.l(rnd, "Output", mean, "Input")
    circ = p.n("CircularSpread", Spread_Count=I(4))
    ii = p.n("I (Spreads)", Start=I(0), End=I(4))
    for name, (node, pin) in [("count", (cnt, "Count")), ("sum", (sm, "Output")),
                              ("slice 1 of reversed", (gs, "Output")),
                              ("sorted", (srt, "Output")), ("mean", (mean, "Output")),
                              ("circle x", (circ, "Output X")), ("circle y", (circ, "Output Y")),
                              ("i", (ii, "Output"))]:
        pr = p.n("Probe", Name=S(name))
        p.l(node, pin, pr, "Input")
    return p

def hdr():
    """A tiny equirectangular sky for Environment (File): Radiance RGBE, uncompressed."""
    w, h = 16, 8
    rows = []
    for y in range(h):
        t = y / (h - 1)
        for x in range(w):
            if t < 0.5:
                r, g, b = 0.4 + 0.6 * t, 0.6 + 0.4 * t, 1.0
            else:
                r, g, b = 0.3, 0.25, 0.2
            if (x, y) == (4, 2):
                r = g = b = 20.0
            m = max(r, g, b)
            import math
            e = math.frexp(m)[1]
            f = 256.0 / (2 ** e)
            rows.append(bytes([int(r * f), int(g * f), int(b * f), e + 128]))
    head = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w)
    with open("patches/assets/help-sky.hdr", "wb") as fh:
        fh.write(head + b"".join(rows))

if __name__ == "__main__":
    hdr()
    for make in [deferred, lighting, shadows, materials, occlusion, environment, post, values, spreads]:
        make().write()
