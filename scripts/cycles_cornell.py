# scripts/cycles_cornell.py — the Cornell box rendered by Blender's Cycles,
# built from the published facts (../shared/assets/cornell/
# cornell_box_facts.json) and not from rtgi's code, so that `rtgi reference`
# can be checked against an independent unbiased renderer
# (scripts/crosscheck-cycles.sh runs both and compares them).
#
# The scene as rtgi builds it (src/core/scene_cornell.c, src/core/scene.c):
#   - every face of the facts, millimetres to metres, a Lambertian diffuse
#     BSDF with the facts' derived linear-sRGB albedo;
#   - the light quad lowered 1 mm below the ceiling, emitting the facts'
#     linear-sRGB radiance (W/(m²·sr)) from its lower side only and black
#     (absorbing, emitting nothing) on its upper side;
#   - the facts' camera (vertical field of view 39.3077°), a box pixel
#     filter one pixel wide (rtgi's reference jitters uniformly inside the
#     pixel), nothing outside the box (black world), no clamping, no
#     denoising, no adaptive sampling, 64 bounces (`--bounces`).
# Cycles' emission shader with strength 1 shows its colour as the pixel's
# value: its colour × strength is the surface's radiance.
#
# blender -b --factory-startup -noaudio -P scripts/cycles_cornell.py -- \
#     --facts FILE.json --size 128x128 --spp 1024 --seed 1 --threads 2 [--bounces N] --out out/cycles.exr
import argparse
import json
import math
import sys

import bpy
from mathutils import Matrix, Vector


def add_render_args(p, size):
    """The options of render() (and of scripts/cycles_mesh.py)."""
    p.add_argument("--size", default=size)
    p.add_argument("--spp", type=int, default=1024)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--threads", type=int, default=0)
    p.add_argument("--filter-width", type=float, default=1.0,
                   help="box pixel filter width in pixels (0.01: pixel centres, as rtgi reference --no-jitter)")
    p.add_argument("--bounces", type=int, default=64,
                   help="indirect bounces (0: direct light only, as rtgi reference --mode direct; "
                        "1: --mode one-bounce; 64: --mode full)")
    p.add_argument("--out", required=True)


def parse_render_args(p):
    """The arguments after Blender's "--", and the image's width and height."""
    a = p.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
    w, h = (int(v) for v in a.size.lower().split("x"))
    if w < 1 or h < 1 or a.spp < 1 or a.bounces < 0:
        p.error("--size and --spp must be positive, --bounces not negative")
    return a, w, h


def parse_args():
    p = argparse.ArgumentParser(prog="cycles_cornell.py")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--facts", help="the Cornell box facts (JSON)")
    src.add_argument("--scene", help="an rtgi scene file of quads, quad lights and a camera")
    add_render_args(p, "128x128")
    return parse_render_args(p)


def node_material(name):
    """A material with an empty node tree but its output node."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    m.node_tree.nodes.clear()
    return m, m.node_tree, m.node_tree.nodes.new("ShaderNodeOutputMaterial")


def diffuse(name, albedo):
    m, nt, out = node_material(name)
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (*albedo, 1.0)
    d.inputs["Roughness"].default_value = 0.0  # Lambert, not Oren-Nayar
    nt.links.new(d.outputs["BSDF"], out.inputs["Surface"])
    return m


def one_sided_emitter(name, radiance):
    m, nt, out = node_material(name)
    peak = max(max(radiance), 1e-30)  # colour in [0, 1], strength the rest (a black light stays black)
    front = nt.nodes.new("ShaderNodeEmission")
    front.inputs["Color"].default_value = (*(c / peak for c in radiance), 1.0)
    front.inputs["Strength"].default_value = peak
    back = nt.nodes.new("ShaderNodeEmission")  # black: absorbs, emits nothing
    back.inputs["Strength"].default_value = 0.0
    geo = nt.nodes.new("ShaderNodeNewGeometry")
    mix = nt.nodes.new("ShaderNodeMixShader")
    nt.links.new(geo.outputs["Backfacing"], mix.inputs["Fac"])
    nt.links.new(front.outputs["Emission"], mix.inputs[1])
    nt.links.new(back.outputs["Emission"], mix.inputs[2])
    nt.links.new(mix.outputs["Shader"], out.inputs["Surface"])
    return m


def quad(name, vertices_m, material):
    """Two triangles (0, 1, 2), (0, 2, 3), shaded with the normal of the
    first corner, (v1 − v0) × (v3 − v0), as rtgi's scene_add_quad builds a
    quad: the same for a planar one, and for the Cornell box's left wall
    (3.2 mm out of plane) the normal rtgi shades it with (with each
    triangle's own normal the red channel of the direct light differed by
    0.07%, 40× the noise)."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices_m, [], [(0, 1, 2), (0, 2, 3)])
    mesh.update()
    v0, v1, v3 = (Vector(vertices_m[i]) for i in (0, 1, 3))
    n = (v1 - v0).cross(v3 - v0).normalized()
    for poly in mesh.polygons:
        poly.use_smooth = True
    mesh.use_auto_smooth = True  # Blender 3.x: custom normals need it
    mesh.normals_split_custom_set([tuple(n)] * len(mesh.loops))
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def add_camera(scene, position, forward, up, fov_y_deg):
    """A pinhole camera at `position` looking along `forward` with `up`,
    `fov_y_deg` vertical field of view (rtgi's camera model)."""
    f = Vector(forward).normalized()
    r = f.cross(Vector(up)).normalized()
    u = r.cross(f)
    data = bpy.data.cameras.new("camera")
    data.sensor_fit = "VERTICAL"
    data.angle_y = math.radians(fov_y_deg)
    data.clip_start = 0.001
    data.clip_end = 1e5
    cam = bpy.data.objects.new("camera", data)
    scene.collection.objects.link(cam)
    # Blender's camera looks down its -z with +y up: columns right, up, back.
    cam.matrix_world = Matrix(((r.x, u.x, -f.x, position[0]), (r.y, u.y, -f.y, position[1]),
                               (r.z, u.z, -f.z, position[2]), (0, 0, 0, 1)))
    scene.camera = cam


def cornell_from_facts(scene, facts):
    colours = facts["derived_linear_srgb"]
    mats = {k: diffuse(k, colours[k]) for k in ("white", "red", "green")}
    emitter = one_sided_emitter("light", colours["light_emission"])
    for name, face in facts["faces"].items():
        v = [tuple(c * 0.001 for c in p) for p in face["vertices"]]
        if face["material"] == "light":
            # Lowered 1 mm; the facts' winding already faces down (-y).
            v = [(x, y - 0.001, z) for x, y, z in v]
            quad(name, v, emitter)
        else:
            quad(name, v, mats[face["material"]])
    cam = facts["camera"]
    add_camera(scene, [c * 0.001 for c in cam["position"]], cam["direction"], cam["up"],
               cam["derived_vertical_fov_deg"])


def from_rtgi_scene(scene, doc):
    """The subset of rtgi's scene format this script knows: "quads"
    (vertices, albedo), quad "lights" (position, direction, radiance, u, v,
    size: the emitter rtgi builds, src/core/scene.c) and "camera" (position,
    target or forward, up, fov_y_deg). Anything else is an error."""
    known = {"quads", "lights", "camera", "exposure"}
    extra = set(doc) - known
    if extra:
        sys.exit("cycles_cornell.py: --scene: keys %s are not supported" % sorted(extra))
    for i, q in enumerate(doc.get("quads", [])):
        quad("quad%d" % i, [tuple(p) for p in q["vertices"]], diffuse("quad%d" % i, q["albedo"]))
    for i, l in enumerate(doc.get("lights", [])):
        if l.get("type") != "quad":
            sys.exit("cycles_cornell.py: --scene: lights[%d]: only quad lights are supported" % i)
        size = l.get("size", 1.0)
        c, d = Vector(l["position"]), Vector(l["direction"])
        hu, hv = Vector(l["u"]) * (0.5 * size), Vector(l["v"]) * (0.5 * size)
        if hu.cross(hv).dot(d) < 0:  # wound so that the normal is the emission direction
            hv = -hv
        v = [tuple(c - hu - hv), tuple(c + hu - hv), tuple(c + hu + hv), tuple(c - hu + hv)]
        quad("light%d" % i, v, one_sided_emitter("light%d" % i, [x / (size * size) for x in l["radiance"]]))
    cam = doc["camera"]
    forward = cam.get("forward") or list(Vector(cam["target"]) - Vector(cam["position"]))
    add_camera(scene, cam["position"], forward, cam.get("up", [0, 1, 0]), cam["fov_y_deg"])


def empty_scene():
    """The factory startup's cube, lamp and camera removed."""
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    return bpy.context.scene


def render(scene, a, w, h, transparent_bounces=0):
    """Renders `scene` to a.out (linear float EXR) with the settings of
    this check: a black world, Cycles on the CPU, a.spp samples without
    adaptive sampling, denoising or clamping, a.bounces diffuse bounces
    (none glossy), a box filter a.filter_width wide, no view transform.
    `transparent_bounces`: how many transparent surfaces (alpha-masked
    texels) a ray may pass (scripts/cycles_mesh.py)."""
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world

    scene.render.engine = "CYCLES"
    cy = scene.cycles
    cy.device = "CPU"
    cy.samples = a.spp
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.seed = a.seed
    cy.max_bounces = cy.diffuse_bounces = a.bounces
    cy.glossy_bounces = cy.transmission_bounces = cy.volume_bounces = 0
    cy.transparent_max_bounces = transparent_bounces
    cy.sample_clamp_direct = cy.sample_clamp_indirect = 0.0
    cy.light_sampling_threshold = 0.0
    cy.filter_type = "BOX"
    cy.filter_width = a.filter_width
    scene.render.resolution_x, scene.render.resolution_y = w, h
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    if a.threads > 0:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = a.threads
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.exr_codec = "ZIP"
    scene.render.filepath = a.out
    scene.render.use_file_extension = False
    bpy.ops.render.render(write_still=True)


def main():
    a, w, h = parse_args()
    scene = empty_scene()
    with open(a.facts or a.scene) as f:
        doc = json.load(f)
    if a.facts:
        cornell_from_facts(scene, doc)
    else:
        from_rtgi_scene(scene, doc)
    render(scene, a, w, h)


if __name__ == "__main__":  # scripts/cycles_mesh.py imports the functions above
    main()
