# scripts/cycles_mesh.py — an rtgi scene file with a glTF mesh (e.g.
# scenes/sponza_nave.json) rendered by Blender's Cycles, so that `rtgi reference`
# can be checked against an independent renderer on textured, alpha-masked
# geometry (scripts/crosscheck-cycles.sh runs both and compares them).
#
# The scene as rtgi builds it (src/core/scene_load.c, src/core/scene.c), from the
# scene file and the glTF file, not from rtgi's code:
#   - the mesh through Blender's own glTF importer, turned back to glTF's
#     +y up and placed by "mesh_scale" and "mesh_translate" (rtgi: T·S·node);
#     the file's normals as shading normals, no normal maps;
#   - every material Lambertian (a Diffuse BSDF, roughness 0), the base
#     colour = baseColorFactor × the baseColorTexture (bilinear, repeat),
#     read from the glTF file itself; rtgi must be run with the same
#     materials made Lambertian ("materials": {name: {"metallic": 0,
#     "specular": 0}}, which crosscheck-cycles.sh writes);
#   - alphaMode MASK: where the texture's alpha × the factor's is below
#     alphaCutoff the surface is transparent (a Transparent BSDF: rays and
#     shadow rays pass), as rtgi's alpha test;
#   - textures decoded to linear floats here (the sRGB formula, as rtgi
#     decodes them before filtering; alpha kept apart from colour), unless
#     --textures byte: Blender's own 8-bit path, which (Cycles 3.4) filters
#     the sRGB-encoded texels and decodes the result;
#   - the scene file's directional lights as sun lamps (strength = the
#     irradiance facing the sun, angle = angular_diameter_deg), its quad
#     lights and quads as scripts/cycles_cornell.py builds them; the camera
#     of the scene file; a black world; shadow terminator offsets 0.
#
# blender -b --factory-startup -noaudio -P scripts/cycles_mesh.py -- \
#     --scene scenes/sponza_nave.json --size 320x180 --spp 1024 --seed 1 --bounces 64 --out out/cycles.exr
# Blender 3.4's glTF importer needs numpy (Debian: python3-numpy).
import argparse
import json
import math
import os
import sys

import bpy
from mathutils import Matrix, Vector

import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cycles_cornell as cc  # noqa: E402 (its helpers: camera, quads, emitters, render settings)

if "bool" not in vars(numpy):  # Blender 3.4's importer uses np.bool, gone in NumPy 1.24 (Debian 12)
    numpy.bool = bool


def parse_args():
    p = argparse.ArgumentParser(prog="cycles_mesh.py")
    p.add_argument("--scene", required=True, help="an rtgi scene file whose \"mesh\" is a glTF file")
    p.add_argument("--textures", choices=("float", "byte"), default="float",
                   help="float: decoded to linear before filtering, as rtgi (default); byte: Blender's 8-bit path")
    p.add_argument("--texture-means", action="store_true",
                   help="print each base-colour texture's mean linear colour (to compare JPEG/PNG decoders)")
    cc.add_render_args(p, "320x180")
    return cc.parse_render_args(p)


def fail(msg):
    sys.exit("cycles_mesh.py: " + msg)


def srgb_decode(c):
    return numpy.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def linear_texture(path, name, means):
    """The image at `path` as a float image of linear colour and straight
    alpha (alpha_mode CHANNEL_PACKED: Cycles leaves the colour as it is
    rather than premultiplying it)."""
    src = bpy.data.images.load(path, check_existing=True)
    w, h = src.size
    px = numpy.empty(w * h * 4, dtype=numpy.float32)
    src.pixels.foreach_get(px)  # a byte image's values / 255, not colour-managed
    px = px.reshape(-1, 4)
    px[:, :3] = srgb_decode(px[:, :3].astype(numpy.float64)).astype(numpy.float32)
    if means:
        m = px.astype(numpy.float64).mean(axis=0)
        print("texture %s: %dx%d linear mean %.4f %.4f %.4f alpha %.3f" % (os.path.basename(path), w, h, *m))
    img = bpy.data.images.new(name, w, h, alpha=True, float_buffer=True)
    img.colorspace_settings.name = "Non-Color"
    img.alpha_mode = "CHANNEL_PACKED"
    img.pixels.foreach_set(px.ravel())
    img.pack()
    return img


def byte_texture(path):
    img = bpy.data.images.load(path, check_existing=True)
    img.colorspace_settings.name = "sRGB"
    img.alpha_mode = "CHANNEL_PACKED"
    return img


def lambert_material(mat, factor, image, cutoff):
    """mat's nodes replaced by a Diffuse BSDF of colour factor × image
    (None: factor alone); with a cutoff (alphaMode MASK), transparent where
    the alpha is below it."""
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    diff = nt.nodes.new("ShaderNodeBsdfDiffuse")
    diff.inputs["Roughness"].default_value = 0.0  # Lambert, not Oren-Nayar
    alpha = None
    if image is not None:
        tex = nt.nodes.new("ShaderNodeTexImage")
        tex.image = image
        tex.interpolation = "Linear"
        tex.extension = "REPEAT"
        mul = nt.nodes.new("ShaderNodeVectorMath")
        mul.operation = "MULTIPLY"
        mul.inputs[1].default_value = factor[:3]
        nt.links.new(tex.outputs["Color"], mul.inputs[0])
        nt.links.new(mul.outputs["Vector"], diff.inputs["Color"])
        alpha = tex.outputs["Alpha"]
    else:
        diff.inputs["Color"].default_value = (*factor[:3], 1.0)
    if cutoff is None:
        nt.links.new(diff.outputs["BSDF"], out.inputs["Surface"])
        return
    a = factor[3] if len(factor) > 3 else 1.0
    below = nt.nodes.new("ShaderNodeMath")  # 1 where alpha × factor < cutoff
    below.operation = "LESS_THAN"
    below.inputs[1].default_value = cutoff
    if alpha is not None:
        scaled = nt.nodes.new("ShaderNodeMath")
        scaled.operation = "MULTIPLY"
        scaled.inputs[1].default_value = a
        nt.links.new(alpha, scaled.inputs[0])
        nt.links.new(scaled.outputs["Value"], below.inputs[0])
    else:
        below.inputs[0].default_value = a
    hole = nt.nodes.new("ShaderNodeBsdfTransparent")
    hole.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    mix = nt.nodes.new("ShaderNodeMixShader")
    nt.links.new(below.outputs["Value"], mix.inputs["Fac"])
    nt.links.new(diff.outputs["BSDF"], mix.inputs[1])
    nt.links.new(hole.outputs["BSDF"], mix.inputs[2])
    nt.links.new(mix.outputs["Shader"], out.inputs["Surface"])


def import_gltf(path, scale, translate, textures, means):
    """Imports the glTF file, places it as rtgi does and gives every
    material its Lambertian version (lambert_material)."""
    if not path.lower().endswith(".gltf"):
        fail("%s: only .gltf meshes (JSON with external buffers) are supported" % path)
    with open(path) as f:
        doc = json.load(f)
    before = set(bpy.data.objects)
    bpy.ops.import_scene.gltf(filepath=path, import_shading="NORMALS", merge_vertices=False)
    # The importer turns glTF's +y up into Blender's +z up, (x, y, z) →
    # (x, −z, y); undo it so that rtgi's coordinates are Blender's.
    to_gltf = Matrix(((1, 0, 0, 0), (0, 0, 1, 0), (0, -1, 0, 0), (0, 0, 0, 1)))
    place = Matrix.Translation(Vector(translate)) @ Matrix.Scale(scale, 4) @ to_gltf
    for obj in set(bpy.data.objects) - before:
        if obj.type != "MESH" and obj.type != "EMPTY":
            bpy.data.objects.remove(obj, do_unlink=True)  # the file's own cameras and lights
        elif obj.parent is None:
            obj.matrix_world = place @ obj.matrix_world
    for obj in bpy.data.objects:
        if obj.type == "MESH":
            obj.cycles.shadow_terminator_offset = 0.0  # rays leave the true surface, as rtgi's
            obj.cycles.shadow_terminator_geometry_offset = 0.0
    base = os.path.dirname(path)
    images = {}
    for i, m in enumerate(doc.get("materials", [])):
        name = m.get("name", "")
        mat = bpy.data.materials.get(name)
        if mat is None:
            fail("%s: material %d (%r) was not imported under its name" % (path, i, name))
        pbr = m.get("pbrMetallicRoughness", {})
        factor = list(pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0]))
        image = None
        if "baseColorTexture" in pbr:
            src = doc["textures"][pbr["baseColorTexture"]["index"]]["source"]
            uri = doc["images"][src].get("uri")
            if uri is None:
                fail("%s: image %d is embedded in a buffer: not supported" % (path, src))
            if src not in images:
                ipath = os.path.join(base, uri)
                images[src] = (linear_texture(ipath, "linear_%d" % src, means) if textures == "float"
                               else byte_texture(ipath))
            image = images[src]
        cutoff = m.get("alphaCutoff", 0.5) if m.get("alphaMode") == "MASK" else None
        if any(m.get("emissiveFactor", [0, 0, 0])):
            fail("%s: material %r emits light: not supported" % (path, name))
        lambert_material(mat, factor, image, cutoff)


def add_sun(i, l):
    """A directional light: irradiance E (W/m², facing it) from a disk of
    angular_diameter_deg, travelling along `direction`."""
    e = l["irradiance"]
    peak = max(max(e), 1e-30)
    data = bpy.data.lights.new("sun%d" % i, "SUN")
    data.energy = peak  # a sun lamp's strength is its irradiance in W/m²
    data.color = tuple(c / peak for c in e)
    data.angle = math.radians(l.get("angular_diameter_deg", 0.53))
    data.cycles.cast_shadow = True
    obj = bpy.data.objects.new("sun%d" % i, data)
    # A sun lamp shines along its local −z.
    d = Vector(l["direction"]).normalized()
    obj.rotation_mode = "QUATERNION"
    obj.rotation_quaternion = Vector((0, 0, -1)).rotation_difference(d)
    bpy.context.scene.collection.objects.link(obj)


def main():
    a, w, h = parse_args()
    scene = cc.empty_scene()
    with open(a.scene) as f:
        doc = json.load(f)
    known = {"mesh", "mesh_scale", "mesh_translate", "quads", "lights", "camera", "exposure", "materials",
             "shadow", "gi"}
    extra = set(doc) - known
    if extra:
        fail("--scene: keys %s are not supported" % sorted(extra))
    if "mesh" not in doc or "camera" not in doc:
        fail("--scene: needs a \"mesh\" and a \"camera\"")
    for name, m in doc.get("materials", {}).items():
        if set(m) - {"metallic", "specular", "roughness"}:
            fail("--scene: materials.%s: only metallic/specular/roughness overrides (made Lambertian here) "
                 "are supported" % name)
    mesh = os.path.join(os.path.dirname(os.path.abspath(a.scene)), doc["mesh"])
    import_gltf(mesh, doc.get("mesh_scale", 1.0), doc.get("mesh_translate", [0, 0, 0]), a.textures,
                a.texture_means)
    quads = {k: doc[k] for k in ("quads", "camera") if k in doc}
    quads["lights"] = [l for l in doc.get("lights", []) if l.get("type") == "quad"]
    for i, l in enumerate(doc.get("lights", [])):
        if l.get("type") == "directional":
            add_sun(i, l)
        elif l.get("type") != "quad":
            fail("--scene: lights[%d]: only directional and quad lights are supported" % i)
    cc.from_rtgi_scene(scene, quads)  # quads, quad lights and the camera
    cc.render(scene, a, w, h, transparent_bounces=64)


main()
