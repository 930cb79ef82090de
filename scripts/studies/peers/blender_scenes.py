"""Builds the Blender test scenes, exports each with Blender's own COLLADA
exporter and renders it with Cycles under settings matched to this renderer's.
Runs inside Blender (Debian's `blender`, 3.4):

  blender -b --factory-startup --python blender_scenes.py -- OUT_DIR \
      [--scenes point_smooth,...] [--samples 256] [--seeds 1,2] [--max-depth 4] [--threads 2] [--export-only]

For each scene it writes OUT_DIR/<scene>.dae (bpy.ops.wm.collada_export) and,
unless --export-only, OUT_DIR/<scene>_cycles_seed<S>.pfm for each seed: two
seeds give two independent halves of one Cycles image. blender_scenes.sh
drives it and compares the halves and their mean with this renderer's render
of the exported .dae.

The scenes cover every light kind Blender exports (point with and without a
radius, sun, spot with a blend, area lights of each shape: square, rectangle,
disk, ellipse), smooth and flat meshes, coloured and emissive materials, and
cameras with a portrait aspect, a non-default sensor width and focal length,
and a non-default sensor fit (Horizontal, in a landscape image, where the
exported field of view is the one Blender uses).

What is matched, and how:
  - diffuse materials are Cycles' Diffuse BSDF (roughness 0: Lambertian) with
    the material's viewport colour set to the same colour, which is what the
    exporter writes as <diffuse> when a material has no Principled BSDF;
    emitters are a Principled BSDF with a black base colour, no specular and an
    emission colour at strength 1 (the exporter drops the strength, and
    divides a colour brighter than 1 by its largest component);
  - the world is black (the exporter does not write it);
  - lights are placed out of the camera's view and with nothing behind them
    (this renderer does not show a point light's disk to camera rays, and an
    area light's back is an opaque black surface here), sun angle 0 (the
    exporter drops it);
  - a box pixel filter 1 pixel wide, no denoising, no clamping, no adaptive
    sampling, every bounce type up to Cycles' max_bounces = -m minus one,
    caustics on, no shadow terminator offsets.
"""

import argparse
import math
import os
import sys

import bpy
import numpy as np

SCENES = ["point_smooth", "sun_flat_emissive", "spot_blend", "area_shapes", "room_horizontal_fit"]


def clear():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    world.color = (0, 0, 0)
    bpy.context.scene.world = world


def diffuse(name, colour):
    m = bpy.data.materials.new(name)
    m.diffuse_color = (*colour, 1.0)  # what the exporter writes without a Principled BSDF
    m.use_nodes = True
    nt = m.node_tree
    for n in list(nt.nodes):
        if n.type != "OUTPUT_MATERIAL":
            nt.nodes.remove(n)
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (*colour, 1.0)
    d.inputs["Roughness"].default_value = 0.0
    nt.links.new(d.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    return m


def emitter(name, colour):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    p = m.node_tree.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (0, 0, 0, 1)
    p.inputs["Specular"].default_value = 0.0
    p.inputs["Emission"].default_value = (*colour, 1.0)
    p.inputs["Emission Strength"].default_value = 1.0
    return m


def finish_object(obj, material, smooth):
    obj.data.materials.clear()
    obj.data.materials.append(material)
    for poly in obj.data.polygons:
        poly.use_smooth = smooth
    for attr in ("shadow_terminator_geometry_offset", "shadow_terminator_offset"):
        for holder in (obj, getattr(obj, "cycles", None)):
            if holder is not None and hasattr(holder, attr):
                setattr(holder, attr, 0.0)
    return obj


def plane(size, location, rotation, material):
    bpy.ops.mesh.primitive_plane_add(size=size, location=location, rotation=rotation)
    return finish_object(bpy.context.active_object, material, False)


def cube(size, location, rotation, material, smooth=False):
    bpy.ops.mesh.primitive_cube_add(size=size, location=location, rotation=rotation)
    return finish_object(bpy.context.active_object, material, smooth)


def sphere(radius, location, material, smooth=True, ico=False):
    if ico:
        bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2, radius=radius, location=location)
    else:
        bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=radius, location=location)
    return finish_object(bpy.context.active_object, material, smooth)


def torus(location, rotation, material):
    bpy.ops.mesh.primitive_torus_add(major_segments=48, minor_segments=16, major_radius=0.8, minor_radius=0.3,
                                     location=location, rotation=rotation)
    return finish_object(bpy.context.active_object, material, True)


def light(name, kind, location, rotation=(0, 0, 0), energy=100.0, colour=(1, 1, 1), **props):
    data = bpy.data.lights.new(name, kind)
    data.energy = energy
    data.color = colour
    if kind == "SUN":
        data.angle = 0.0
    elif kind in ("POINT", "SPOT"):
        data.shadow_soft_size = props.pop("radius", 0.0)
    for k, v in props.items():
        setattr(data, k, v)
    obj = bpy.data.objects.new(name, data)
    obj.location = location
    obj.rotation_euler = rotation
    bpy.context.scene.collection.objects.link(obj)
    return obj


def camera(location, look_at, lens=50.0, sensor_width=36.0, fit="AUTO", size=(160, 120)):
    data = bpy.data.cameras.new("Camera")
    data.lens = lens
    data.sensor_width = sensor_width
    data.sensor_fit = fit
    data.clip_start, data.clip_end = 0.05, 100.0
    obj = bpy.data.objects.new("Camera", data)
    obj.location = location
    direction = (np.array(look_at, dtype=float) - np.array(location, dtype=float)).tolist()
    from mathutils import Vector
    obj.rotation_euler = Vector(direction).to_track_quat("-Z", "Y").to_euler()
    bpy.context.scene.collection.objects.link(obj)
    sc = bpy.context.scene
    sc.camera = obj
    sc.render.resolution_x, sc.render.resolution_y = size
    sc.render.resolution_percentage = 100


def build(name):
    clear()
    grey, red, green = diffuse("Grey", (0.8, 0.8, 0.8)), diffuse("Red", (0.8, 0.1, 0.1)), diffuse("Green", (0.1, 0.7, 0.2))
    if name == "point_smooth":  # point lights, with and without a radius; smooth and flat meshes
        plane(20, (0, 0, 0), (0, 0, 0), grey)
        plane(20, (0, 4, 0), (math.pi / 2, 0, 0), grey)
        torus((0, 0, 0.9), (math.radians(70), 0, math.radians(20)), red)
        cube(1.0, (1.8, 0.8, 0.5), (0, 0, 0.4), green)
        sphere(0.6, (-1.8, 0.5, 0.6), grey)
        light("Point", "POINT", (1.5, -2.5, 3.5), energy=800.0, colour=(1.0, 0.9, 0.8))
        light("SoftPoint", "POINT", (-2.5, -1.0, 2.5), energy=300.0, colour=(0.6, 0.7, 1.0), radius=0.3)
        camera((0, -7, 3), (0, 0, 0.8))
    elif name == "sun_flat_emissive":  # a sun; flat meshes; an emissive material
        plane(20, (0, 0, 0), (0, 0, 0), grey)
        cube(1.2, (-1.0, 0, 0.6), (0, 0, 0.3), red)
        sphere(0.7, (1.0, 0.3, 0.7), green, smooth=False, ico=True)
        cube(0.6, (0.2, 1.8, 0.3), (0, 0, 0), emitter("Glow", (1.0, 0.6, 0.2)))
        light("Sun", "SUN", (0, 0, 10), rotation=(math.radians(40), 0, math.radians(30)), energy=2.5)
        camera((0, -6, 3.5), (0, 0.4, 0.5))
    elif name == "spot_blend":  # a spot cone with a soft edge
        plane(20, (0, 0, 0), (0, 0, 0), grey)
        plane(20, (0, 3, 0), (math.pi / 2, 0, 0), grey)
        sphere(0.7, (0.3, 0.5, 0.7), red)
        light("Spot", "SPOT", (0, -1.5, 4.5), rotation=(math.radians(20), 0, 0), energy=1500.0,
              spot_size=math.radians(50), spot_blend=0.4)
        camera((0, -6, 2.5), (0, 0.5, 0.8))
    elif name == "area_shapes":  # area lights of every shape; a portrait image with a 24 mm sensor, 35 mm lens
        plane(20, (0, 0, 0), (0, 0, 0), grey)
        sphere(0.5, (0, 0.3, 0.5), grey)
        light("Square", "AREA", (-1.2, -0.8, 2.0), energy=150.0, colour=(1.0, 0.5, 0.5), shape="SQUARE", size=0.6)
        light("Rectangle", "AREA", (1.2, -0.8, 2.2), energy=150.0, colour=(0.5, 1.0, 0.5), shape="RECTANGLE",
              size=1.0, size_y=0.3)
        light("Disk", "AREA", (-1.2, 1.4, 2.4), rotation=(math.radians(-20), 0, 0), energy=150.0,
              colour=(0.5, 0.5, 1.0), shape="DISK", size=0.8)
        light("Ellipse", "AREA", (1.2, 1.4, 2.0), rotation=(0, math.radians(15), 0), energy=150.0,
              shape="ELLIPSE", size=1.2, size_y=0.4)
        camera((0, -4.0, 1.2), (0, 0.5, 0), lens=35.0, sensor_width=24.0, size=(120, 160))
    elif name == "room_horizontal_fit":  # a closed room, a rectangular ceiling light, Horizontal sensor fit
        white = diffuse("White", (0.75, 0.75, 0.75))
        plane(4, (0, 0, 0), (0, 0, 0), white)
        # The ceiling has an opening the size of the light, which sits 1 cm above it (a light well): an
        # area light's back is an opaque surface here and transparent in Cycles, so nothing may face it.
        for cx, cy, sx, sy in ((-1.3, 0, 1.4, 4), (1.3, 0, 1.4, 4), (0, -1.2, 1.2, 1.6), (0, 1.2, 1.2, 1.6)):
            plane(1, (cx, cy, 4), (math.pi, 0, 0), white).scale = (sx, sy, 1)
        plane(4, (0, 2, 2), (math.pi / 2, 0, 0), white)
        plane(4, (-2, 0, 2), (0, math.pi / 2, 0), red)
        plane(4, (2, 0, 2), (0, -math.pi / 2, 0), green)
        plane(4, (0, -2, 2), (-math.pi / 2, 0, 0), white)
        sphere(0.6, (-0.7, 0.4, 0.6), white)
        cube(1.0, (0.7, 0.6, 0.5), (0, 0, 0.5), white)
        light("Ceiling", "AREA", (0, 0, 4.01), energy=120.0, shape="RECTANGLE", size=1.2, size_y=0.8)
        camera((0, -1.9, 2.0), (0, 0, 1.4), lens=18.0, fit="HORIZONTAL", size=(160, 120))
    else:
        raise SystemExit(f"blender_scenes: unknown scene {name}")


def configure(max_depth, threads, seed, samples):
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    cy = sc.cycles
    cy.device = "CPU"
    cy.samples = samples
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 1.0
    cy.sample_clamp_direct = cy.sample_clamp_indirect = 0.0
    cy.blur_glossy = 0.0
    cy.caustics_reflective = cy.caustics_refractive = True
    bounces = max(0, max_depth - 1)
    cy.max_bounces = bounces
    cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = bounces
    cy.volume_bounces = cy.transparent_max_bounces = bounces
    cy.seed = seed
    cy.use_animated_seed = False
    sc.render.threads_mode = "FIXED"
    sc.render.threads = threads
    sc.render.film_transparent = False
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.view_settings.exposure = 0.0
    sc.view_settings.gamma = 1.0
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    sc.render.image_settings.exr_codec = "NONE"


def write_pfm(path, rgba_bottom_up, width, height):
    """Little-endian RGB PFM; Blender's pixels and PFM both start at the bottom row."""
    rgb = np.ascontiguousarray(rgba_bottom_up.reshape(height, width, 4)[:, :, :3], dtype="<f4")
    with open(path + ".tmp", "wb") as f:
        f.write(f"PF\n{width} {height}\n-1.0\n".encode())
        f.write(rgb.tobytes())
    os.replace(path + ".tmp", path)


def render(path):
    sc = bpy.context.scene
    exr = path + ".exr"
    sc.render.filepath = exr
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(exr)
    w, h = sc.render.resolution_x, sc.render.resolution_y
    pixels = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(pixels)
    bpy.data.images.remove(img)
    write_pfm(path, pixels, w, h)
    os.remove(exr)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("out_dir")
    p.add_argument("--scenes", default=",".join(SCENES))
    p.add_argument("--samples", type=int, default=256)
    p.add_argument("--seeds", default="1,2")
    p.add_argument("--max-depth", type=int, default=4)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--export-only", action="store_true")
    args = p.parse_args(argv)
    os.makedirs(args.out_dir, exist_ok=True)
    for name in args.scenes.split(","):
        build(name)
        dae = os.path.join(args.out_dir, f"{name}.dae")
        bpy.ops.wm.collada_export(filepath=dae)
        sc = bpy.context.scene
        print(f"blender_scenes: {name}: exported {dae} ({sc.render.resolution_x}x{sc.render.resolution_y})")
        if args.export_only:
            continue
        for seed in [int(s) for s in args.seeds.split(",")]:
            configure(args.max_depth, args.threads, seed, args.samples)
            out = os.path.join(args.out_dir, f"{name}_cycles_seed{seed}.pfm")
            render(out)
            print(f"blender_scenes: {name}: Cycles {args.samples} spp, seed {seed} -> {out}")


main()
