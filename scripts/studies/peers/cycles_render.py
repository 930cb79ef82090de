"""Renders a scene exported by `pathtracer --export-scene` with Blender's Cycles,
under settings matched to this renderer's, and writes each render as a linear
float PFM with its wall time. Runs inside Blender:

  blender -b --factory-startup --python cycles_render.py -- SCENE.json OUT_DIR \
      --samples 16,64,256 --max-depth 5 --threads 2 [--repeats 3] [--seed 0]

What is matched (and how):
  - geometry: the exported triangles with this renderer's smooth vertex normals
    (custom split normals), spheres as Cycles point-cloud spheres (exact);
  - camera: position, orientation and horizontal field of view; a box pixel
    filter 1 pixel wide (uniform jitter inside the pixel);
  - Lambertian diffuse as the Diffuse BSDF; mirrors as the sharp Glossy BSDF
    (no Fresnel, as here); glass as a Fresnel-weighted mix of the sharp
    Refraction (transmittance) and Glossy (reflectance) BSDFs, refraction-only
    materials as the sharp Refraction BSDF;
  - each area light as its two one-sided emissive triangles at the file's
    radiance (emission strength 1 is radiance 1 in Cycles); point lights
    without distance falloff (the Light Falloff node's constant output; Cycles'
    point light of power P has intensity P / (4 pi)); directional lights as sun
    lamps of angle 0 (strength = irradiance); the sky as a world colour over the
    upper hemisphere only;
  - light transport: Cycles' max_bounces = this renderer's -m minus one (its
    first bounce is this renderer's second), every bounce type up to it,
    caustics on, no clamping, no glossy filter, no denoising, no adaptive
    sampling; Cycles' own sampling pattern, light sampling and Russian roulette
    (its defaults, as a user renders).
  - no shadow terminator offsets (this renderer has none).
What cannot be matched is refused with the reason (exit code 3): microfacet
conductors (Cycles 3.4's Glossy BSDF has no conductor Fresnel, and its Beckmann
shadowing is separable, not the height-correlated Smith G used here), glass
with smooth shading normals (the two renderers treat directions below the
shading horizon differently), shading normals far from the geometric normal on
more than 5% of the surface (for the same reason), an environment map (-e) and
a thin lens (-b).
"""

import argparse
import json
import math
import os
import sys
import time

import bpy
import mathutils
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))  # scripts/: ptlib
from ptlib.images import write_pfm  # noqa: E402


def to_blender(v):
    """This renderer's world (Y up) to Blender's (Z up): +90 degrees about X."""
    return (v[0], -v[2], v[1])


def smooth_refractive_triangles(doc):
    """Triangles of glass or refraction whose vertex normals differ from the
    face normal (smooth-shaded facets)."""
    refractive = [i for i, m in enumerate(doc["materials"]) if m["kind"] in ("glass", "refraction")]
    if not refractive or not doc["triangles"]:
        return 0
    p = np.asarray(doc["positions"], dtype=np.float64).reshape(-1, 3)
    n = np.asarray(doc["normals"], dtype=np.float64).reshape(-1, 3)
    t = np.asarray(doc["triangles"], dtype=np.int64).reshape(-1, 4)
    t = t[np.isin(t[:, 3], refractive)]
    face = np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]])
    face /= np.maximum(np.linalg.norm(face, axis=1), 1e-30)[:, None]
    cos = np.min([np.sum(n[t[:, k]] * face, axis=1) for k in range(3)], axis=0)
    return int(np.count_nonzero(cos < 0.9999))


def far_shading_normals(doc, degrees=45.0):
    """Share of the triangles' area where a vertex normal is more than
    `degrees` from the face normal (smoothing across sharp edges)."""
    if not doc["triangles"]:
        return 0.0
    p = np.asarray(doc["positions"], dtype=np.float64).reshape(-1, 3)
    n = np.asarray(doc["normals"], dtype=np.float64).reshape(-1, 3)
    t = np.asarray(doc["triangles"], dtype=np.int64).reshape(-1, 4)
    face = np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]])
    area = np.linalg.norm(face, axis=1)
    face /= np.maximum(area, 1e-30)[:, None]
    cos = np.min([np.sum(n[t[:, k]] * face, axis=1) for k in range(3)], axis=0)
    return float(area[cos < math.cos(math.radians(degrees))].sum() / max(area.sum(), 1e-30))


def unmatched_features(doc):
    reasons = []
    far = far_shading_normals(doc)
    if far > 0.05:
        reasons.append(f"shading normals more than 45 degrees from the geometric normal on {100 * far:.0f}% of the "
                       "surface (smoothing across sharp edges): the two renderers treat directions between the "
                       "shading and the geometric horizon differently; on banana the converged images differ by 2-4% "
                       "on the tray's edges")
    smooth = smooth_refractive_triangles(doc)
    if smooth:
        reasons.append(f"glass with smooth shading normals ({smooth} triangles): this renderer ends a path whose "
                       "direction falls below the shading normal's horizon at a refraction, Cycles 3.4 treats such "
                       "directions its own way; on CBgems the converged images differ by about 2% on and around "
                       "the glass")
    if any(m["kind"] == "microfacet" for m in doc["materials"]):
        reasons.append("microfacet conductors: Cycles 3.4's Glossy BSDF has no conductor Fresnel (eta, k) and "
                       "its Beckmann shadowing is separable, not the height-correlated Smith G of this renderer")
    if any(l.get("inverse_square") for l in doc["point_lights"]) or \
            any(l.get("shape", "parallelogram") != "parallelogram" for l in doc["area_lights"]):
        reasons.append("Blender's lights (falloff, radius, spot cone, elliptical area lights): a Blender export is "
                       "compared with Cycles by scripts/studies/peers/blender_scenes.sh, which renders Blender's own scene")
    if doc["environment_map"]:
        reasons.append("an environment map (-e): its lookup and sampling conventions are not mapped to Cycles")
    if doc["camera"]["lens_radius"] > 0:
        reasons.append("a thin lens (-b): Cycles' aperture is not mapped")
    return reasons


def clear_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def node_material(name):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        if n.type != "OUTPUT_MATERIAL":
            nt.nodes.remove(n)
    return mat, nt, nt.nodes["Material Output"]


def rgba(c):
    return (c[0], c[1], c[2], 1.0)


def emission_shader(nt, m):
    """Emission of a material; one-sided emitters are black from behind
    (Backfacing is the triangle's winding, which this renderer sets to the
    emitting side)."""
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Color"].default_value = rgba(m["emission"])
    if m["one_sided"]:
        geo = nt.nodes.new("ShaderNodeNewGeometry")
        front = nt.nodes.new("ShaderNodeMath")
        front.operation = "SUBTRACT"
        front.inputs[0].default_value = 1.0
        nt.links.new(geo.outputs["Backfacing"], front.inputs[1])
        nt.links.new(front.outputs[0], em.inputs["Strength"])
    else:
        em.inputs["Strength"].default_value = 1.0
    return em


def make_material(i, m):
    mat, nt, out = node_material(f"m{i}")
    kind = m["kind"]
    if kind == "diffuse":
        surface = None
        if any(c > 0 for c in m["albedo"]):
            surface = nt.nodes.new("ShaderNodeBsdfDiffuse")
            surface.inputs["Color"].default_value = rgba(m["albedo"])
            surface.inputs["Roughness"].default_value = 0.0
        if any(c > 0 for c in m["emission"]):
            em = emission_shader(nt, m)
            if surface is None:
                surface = em
            else:
                add = nt.nodes.new("ShaderNodeAddShader")
                nt.links.new(surface.outputs[0], add.inputs[0])
                nt.links.new(em.outputs[0], add.inputs[1])
                surface = add
        if surface is None:  # black: absorbs everything
            surface = nt.nodes.new("ShaderNodeEmission")
            surface.inputs["Strength"].default_value = 0.0
    elif kind == "mirror":
        surface = nt.nodes.new("ShaderNodeBsdfGlossy")
        surface.distribution = "SHARP"
        surface.inputs["Color"].default_value = rgba(m["albedo"])
    elif kind in ("glass", "refraction"):
        refr = nt.nodes.new("ShaderNodeBsdfRefraction")
        refr.distribution = "SHARP"
        refr.inputs["Color"].default_value = rgba(m["transmittance"])
        refr.inputs["IOR"].default_value = m["ior"]
        surface = refr
        if kind == "glass":
            refl = nt.nodes.new("ShaderNodeBsdfGlossy")
            refl.distribution = "SHARP"
            refl.inputs["Color"].default_value = rgba(m["albedo"])
            fresnel = nt.nodes.new("ShaderNodeFresnel")
            fresnel.inputs["IOR"].default_value = m["ior"]
            mix = nt.nodes.new("ShaderNodeMixShader")
            nt.links.new(fresnel.outputs[0], mix.inputs["Fac"])
            nt.links.new(refr.outputs[0], mix.inputs[1])
            nt.links.new(refl.outputs[0], mix.inputs[2])
            surface = mix
    else:
        raise ValueError(f"material kind {kind} is not matched")
    nt.links.new(surface.outputs[0], out.inputs["Surface"])
    return mat


def add_mesh(doc, materials):
    pos = np.asarray(doc["positions"], dtype=np.float64).reshape(-1, 3)
    nrm = np.asarray(doc["normals"], dtype=np.float64).reshape(-1, 3)
    tris = np.asarray(doc["triangles"], dtype=np.int64).reshape(-1, 4)
    if len(tris) == 0:
        return
    verts = [to_blender(p) for p in pos]
    mesh = bpy.data.meshes.new("scene")
    mesh.from_pydata(verts, [], [tuple(int(v) for v in t[:3]) for t in tris])
    for m in materials:
        mesh.materials.append(m)
    mesh.polygons.foreach_set("material_index", tris[:, 3].astype(np.int32))
    mesh.polygons.foreach_set("use_smooth", np.ones(len(tris), dtype=bool))
    mesh.use_auto_smooth = True
    mesh.normals_split_custom_set_from_vertices([to_blender(n) for n in nrm])
    mesh.update()
    obj = bpy.data.objects.new("scene", mesh)
    no_terminator_offsets(obj)
    bpy.context.scene.collection.objects.link(obj)


def no_terminator_offsets(obj):
    """This renderer traces shadow rays from the true surface: Cycles' shadow
    terminator offsets (by default 0.1 of the geometry offset) would soften the
    terminator of smooth-shaded coarse meshes (cow, beetle) that this renderer
    shows hard."""
    for name in ("shadow_terminator_geometry_offset", "shadow_terminator_offset"):
        if hasattr(obj, name):
            setattr(obj, name, 0.0)
        elif hasattr(obj, "cycles") and hasattr(obj.cycles, name):
            setattr(obj.cycles, name, 0.0)


def add_sphere(i, s, material):
    """An exact sphere: one point of a Cycles point cloud (Mesh to Points)."""
    mesh = bpy.data.meshes.new(f"sphere{i}")
    mesh.from_pydata([to_blender(s["centre"])], [], [])
    obj = bpy.data.objects.new(f"sphere{i}", mesh)
    bpy.context.scene.collection.objects.link(obj)
    ng = bpy.data.node_groups.new(f"points{i}", "GeometryNodeTree")
    ng.inputs.new("NodeSocketGeometry", "Geometry")
    ng.outputs.new("NodeSocketGeometry", "Geometry")
    gin, gout = ng.nodes.new("NodeGroupInput"), ng.nodes.new("NodeGroupOutput")
    to_points = ng.nodes.new("GeometryNodeMeshToPoints")
    to_points.inputs["Radius"].default_value = s["radius"]
    set_mat = ng.nodes.new("GeometryNodeSetMaterial")
    set_mat.inputs["Material"].default_value = material
    ng.links.new(gin.outputs[0], to_points.inputs["Mesh"])
    ng.links.new(to_points.outputs["Points"], set_mat.inputs["Geometry"])
    ng.links.new(set_mat.outputs["Geometry"], gout.inputs[0])
    mod = obj.modifiers.new("points", "NODES")
    mod.node_group = ng


def add_point_light(i, l):
    """No distance falloff: the Light Falloff node's constant output cancels the
    1 / r^2, and power 4 pi makes the irradiance at normal incidence the
    radiance this renderer's point light gives (Cycles' intensity is P / 4 pi)."""
    data = bpy.data.lights.new(f"point{i}", "POINT")
    data.energy = 4.0 * math.pi
    data.shadow_soft_size = 0.0
    data.color = (1.0, 1.0, 1.0)
    data.use_nodes = True
    nt = data.node_tree
    falloff = nt.nodes.new("ShaderNodeLightFalloff")
    falloff.inputs["Strength"].default_value = 1.0
    nt.nodes["Emission"].inputs["Color"].default_value = rgba(l["radiance"])
    nt.links.new(falloff.outputs["Constant"], nt.nodes["Emission"].inputs["Strength"])
    obj = bpy.data.objects.new(f"point{i}", data)
    obj.location = to_blender(l["position"])
    bpy.context.scene.collection.objects.link(obj)


def add_sun(i, l):
    """A sun of angle 0 shining along -to_light; its strength is the irradiance."""
    data = bpy.data.lights.new(f"sun{i}", "SUN")
    data.angle = 0.0
    data.energy = 1.0
    data.use_nodes = True
    data.node_tree.nodes["Emission"].inputs["Color"].default_value = rgba(l["radiance"])
    obj = bpy.data.objects.new(f"sun{i}", data)
    d = np.asarray(to_blender(l["to_light"]), dtype=np.float64)
    d /= np.linalg.norm(d)
    # The sun shines along its local -Z: rotate +Z onto d.
    z = np.array([0.0, 0.0, 1.0])
    axis = np.cross(z, d)
    if np.linalg.norm(axis) < 1e-9:
        axis, angle = np.array([1.0, 0.0, 0.0]), (0.0 if d[2] > 0 else math.pi)
    else:
        angle = math.acos(max(-1.0, min(1.0, float(np.dot(z, d)))))
        axis /= np.linalg.norm(axis)
    obj.rotation_mode = "AXIS_ANGLE"
    obj.rotation_axis_angle = (angle, axis[0], axis[1], axis[2])
    bpy.context.scene.collection.objects.link(obj)


def set_world(doc):
    world = bpy.data.worlds.new("world")
    bpy.context.scene.world = world
    world.use_nodes = True
    nt = world.node_tree
    bg = nt.nodes["Background"]
    if doc["sky"] is None:
        bg.inputs["Strength"].default_value = 0.0
        world.cycles.sampling_method = "NONE"
        return
    # Uniform radiance over the upper hemisphere of directions (Blender's +Z).
    coords = nt.nodes.new("ShaderNodeTexCoord")
    xyz = nt.nodes.new("ShaderNodeSeparateXYZ")
    above = nt.nodes.new("ShaderNodeMath")
    above.operation = "GREATER_THAN"
    above.inputs[1].default_value = 0.0
    nt.links.new(coords.outputs["Generated"], xyz.inputs[0])
    nt.links.new(xyz.outputs["Z"], above.inputs[0])
    nt.links.new(above.outputs[0], bg.inputs["Strength"])
    bg.inputs["Color"].default_value = rgba(doc["sky"])


def set_camera(doc):
    c = doc["camera"]
    data = bpy.data.cameras.new("camera")
    data.sensor_fit = "HORIZONTAL"
    data.lens_unit = "FOV"
    data.angle = 2.0 * math.atan(c["tan_half_hfov"])
    data.clip_start = c["near_clip"]
    data.clip_end = c["far_clip"]
    obj = bpy.data.objects.new("camera", data)
    right, up, back = (np.asarray(to_blender(c[k])) for k in ("screen_x", "screen_y", "to_camera"))
    m = np.identity(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = right, up, back, to_blender(c["position"])
    obj.matrix_world = mathutils.Matrix([list(row) for row in m])  # rows
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.scene.camera = obj
    expect_v = c["tan_half_hfov"] * doc["height"] / doc["width"]
    if abs(expect_v - c["tan_half_vfov"]) > 1e-4 * expect_v:
        raise ValueError("the exported camera's pixels are not square; Cycles' field of view would differ")


def configure(doc, args):
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    cy = sc.cycles
    cy.device = "CPU"
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 1.0
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.blur_glossy = 0.0
    cy.caustics_reflective = True
    cy.caustics_refractive = True
    bounces = max(0, args.max_depth - 1)
    cy.max_bounces = bounces
    cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = bounces
    cy.volume_bounces = cy.transparent_max_bounces = bounces
    cy.seed = args.seed
    cy.use_animated_seed = False
    sc.render.resolution_x, sc.render.resolution_y = doc["width"], doc["height"]
    sc.render.resolution_percentage = 100
    sc.render.threads_mode = "FIXED"
    sc.render.threads = args.threads
    sc.render.film_transparent = False
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.view_settings.exposure = 0.0
    sc.view_settings.gamma = 1.0
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    sc.render.image_settings.exr_codec = "NONE"


def save_pfm(path, rgba_bottom_up, width, height):
    """Blender's pixels (RGBA, bottom row first) as a linear RGB PFM (ptlib.images.write_pfm takes the top row first)."""
    write_pfm(path, rgba_bottom_up.reshape(height, width, 4)[::-1, :, :3])


def render(out_dir, spp, repeats, doc):
    sc = bpy.context.scene
    sc.cycles.samples = spp
    exr = os.path.join(out_dir, f"cycles_s{spp}.exr")
    sc.render.filepath = exr
    seconds = []
    for r in range(repeats):
        start = time.perf_counter()
        bpy.ops.render.render(write_still=(r == 0))
        seconds.append(time.perf_counter() - start)
    img = bpy.data.images.load(exr)
    pixels = np.empty(doc["width"] * doc["height"] * 4, dtype=np.float32)
    img.pixels.foreach_get(pixels)
    bpy.data.images.remove(img)
    save_pfm(os.path.join(out_dir, f"cycles_s{spp}.pfm"), pixels, doc["width"], doc["height"])
    os.remove(exr)
    return seconds


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="cycles_render.py")
    p.add_argument("scene_json")
    p.add_argument("out_dir")
    p.add_argument("--samples", default="16,64,256")
    p.add_argument("--max-depth", type=int, default=5)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--repeats", type=int, default=1)
    p.add_argument("--seed", type=int, default=0)
    args = p.parse_args(argv)
    with open(args.scene_json) as f:
        doc = json.load(f)
    reasons = unmatched_features(doc)
    if reasons:
        for r in reasons:
            print(f"cycles_render: {doc['scene']}: not matched: {r}", file=sys.stderr)
        sys.stdout.flush()
        os._exit(3)
    clear_scene()
    materials = [make_material(i, m) for i, m in enumerate(doc["materials"])]
    add_mesh(doc, materials)
    for i, s in enumerate(doc["spheres"]):
        add_sphere(i, s, materials[s["material"]])
    for i, l in enumerate(doc["point_lights"]):
        add_point_light(i, l)
    for i, l in enumerate(doc["directional_lights"]):
        add_sun(i, l)
    set_world(doc)
    set_camera(doc)
    configure(doc, args)
    os.makedirs(args.out_dir, exist_ok=True)
    bpy.context.scene.cycles.samples = 1  # a warm-up render, not timed: kernels and caches loaded once
    bpy.context.scene.render.filepath = os.path.join(args.out_dir, "warmup.exr")
    bpy.ops.render.render(write_still=False)
    times = {}
    for spp in (int(s) for s in args.samples.split(",")):
        times[spp] = render(args.out_dir, spp, args.repeats, doc)
        print(f"cycles_render: {doc['scene']} {spp} spp: {min(times[spp]):.3f} s", flush=True)
    path = os.path.join(args.out_dir, "cycles_times.json")
    with open(path, "w") as f:
        json.dump({"blender": bpy.app.version_string, "threads": args.threads, "seconds": times}, f)


try:
    main()
except SystemExit:
    raise
except BaseException as e:  # Blender keeps running after a script error; make it a failure
    print(f"cycles_render: error: {e}", file=sys.stderr)
    sys.stdout.flush()
    os._exit(1)
sys.stdout.flush()
os._exit(0)
