// The fixed Python of the Cycles export (integrands/scenes/cycles_export.h): scene.py's functions,
// which build the scene from its data block, and render.py. Kept as Python text here so that the
// binary needs no data files.
#include "integrands/scenes/cycles_export.h"

namespace pcbench::scene {

// scene.py after its data block: WIDTH, HEIGHT, CYCLES_BOUNCES, CAMERA, MATERIALS (kind, name,
// albedo, exponent), GROUPS (material, emission, vertices: three per triangle) and POINT_LIGHTS.
const char* cycles_scene_functions() {
  return R"py(
import math

import bpy
from mathutils import Matrix, Vector


def _material(name, kind, albedo, exponent, emission):
    """A Cycles material: pcbench's scattering (two-sided) plus its emission, front side only."""
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    nodes.clear()
    output = nodes.new("ShaderNodeOutputMaterial")
    if kind == "diffuse":
        surface = nodes.new("ShaderNodeBsdfDiffuse")
        surface.inputs["Roughness"].default_value = 0.0  # Lambertian, not Oren-Nayar
    else:
        surface = nodes.new("ShaderNodeBsdfGlossy")
        if kind == "mirror":
            surface.distribution = "SHARP"
        else:  # phong, written only with --approximate: a Beckmann lobe of similar width
            surface.distribution = "BECKMANN"
            surface.inputs["Roughness"].default_value = (2.0 / (exponent + 2.0)) ** 0.25
    surface.inputs["Color"].default_value = (*albedo, 1.0)
    if max(emission) == 0.0:
        links.new(surface.outputs["BSDF"], output.inputs["Surface"])
        return material
    # Cycles' emission shader gives radiance Color x Strength on both sides; pcbench's emitters
    # radiate from the front side only (the side cross(p1 - p0, p2 - p0) points to, which is
    # Blender's face normal for the same vertex order): the back side mixes to no emission.
    strength = max(emission)
    emit = nodes.new("ShaderNodeEmission")
    emit.inputs["Color"].default_value = (*(e / strength for e in emission), 1.0)
    emit.inputs["Strength"].default_value = strength
    geometry = nodes.new("ShaderNodeNewGeometry")
    front_only = nodes.new("ShaderNodeMixShader")
    links.new(geometry.outputs["Backfacing"], front_only.inputs["Fac"])
    links.new(emit.outputs["Emission"], front_only.inputs[1])
    add = nodes.new("ShaderNodeAddShader")
    links.new(surface.outputs["BSDF"], add.inputs[0])
    links.new(front_only.outputs["Shader"], add.inputs[1])
    links.new(add.outputs["Shader"], output.inputs["Surface"])
    return material


def _camera(scene):
    """pcbench's pinhole camera: vertical field of view, right = forward x up."""
    position, look_at, up = (Vector(CAMERA[key]) for key in ("position", "look_at", "up"))
    forward = (look_at - position).normalized()
    right = forward.cross(up).normalized()
    true_up = right.cross(forward)
    data = bpy.data.cameras.new("camera")
    data.type = "PERSP"
    data.sensor_fit = "VERTICAL"
    data.angle_y = math.radians(CAMERA["fov_degrees"])
    data.shift_x = data.shift_y = 0.0
    data.clip_start = 1e-6
    data.clip_end = 1e9
    camera = bpy.data.objects.new("camera", data)
    # A Blender camera looks down its -Z with +Y up and +X right.
    camera.matrix_world = Matrix((
        (right.x, true_up.x, -forward.x, position.x),
        (right.y, true_up.y, -forward.y, position.y),
        (right.z, true_up.z, -forward.z, position.z),
        (0.0, 0.0, 0.0, 1.0),
    ))
    scene.collection.objects.link(camera)
    scene.camera = camera


def _settings(scene):
    """Every Cycles setting that would bias it or make it render another image than pcbench."""
    render = scene.render
    render.engine = "CYCLES"
    render.resolution_x, render.resolution_y = WIDTH, HEIGHT
    render.resolution_percentage = 100
    render.pixel_aspect_x = render.pixel_aspect_y = 1.0
    render.film_transparent = False
    render.use_motion_blur = False
    render.use_compositing = False
    render.use_sequencer = False
    render.use_border = False
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.feature_set = "SUPPORTED"
    cycles.use_adaptive_sampling = False  # on by default: stops pixels early, on their own noise
    cycles.light_sampling_threshold = 0.0  # 0.01 by default: drops dim light samples
    cycles.sample_clamp_direct = 0.0  # 0: no clamping
    cycles.sample_clamp_indirect = 0.0  # 10 by default: clips bright indirect paths
    cycles.blur_glossy = 0.0  # filter glossy: blurs sharp reflections
    cycles.caustics_reflective = True
    cycles.caustics_refractive = True
    cycles.use_denoising = False
    cycles.use_preview_denoising = False
    cycles.use_fast_gi = False
    cycles.use_guiding = False  # path guiding carries state between samples
    cycles.pixel_filter_type = "BOX"  # pcbench's pixel: the box of one pixel
    cycles.filter_width = 1.0  # Blackman-Harris 1.5 px by default
    cycles.use_animated_seed = False
    cycles.auto_scrambling_distance = False
    cycles.scrambling_distance = 1.0
    cycles.min_light_bounces = 0
    cycles.min_transparent_bounces = 0
    cycles.film_exposure = 1.0
    cycles.time_limit = 0.0
    bounces = CYCLES_BOUNCES
    cycles.max_bounces = bounces
    cycles.diffuse_bounces = bounces
    cycles.glossy_bounces = bounces
    cycles.transmission_bounces = bounces
    cycles.transparent_max_bounces = bounces
    cycles.volume_bounces = 0
    for layer in scene.view_layers:
        layer.cycles.use_denoising = False
    # A black world: pcbench's scenes have no light from outside.
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    background.inputs["Strength"].default_value = 0.0
    scene.world = world
    # Linear radiance, written as 32-bit float EXR (no view transform reaches an EXR; Standard
    # keeps any preview linear too).
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    image = render.image_settings
    image.file_format = "OPEN_EXR"
    image.color_depth = "32"
    image.color_mode = "RGB"
    image.exr_codec = "ZIP"


def build(scene):
    """Builds the scene into `scene`, an empty one (read_factory_settings(use_empty=True))."""
    _settings(scene)
    materials = {}
    for index, group in enumerate(GROUPS):
        kind, name, albedo, exponent = MATERIALS[group["material"]]
        material = _material(f"{name}.{index}", kind, albedo, exponent, group["emission"])
        mesh = bpy.data.meshes.new(f"{name}.{index}")
        vertices = group["vertices"]
        faces = [(3 * i, 3 * i + 1, 3 * i + 2) for i in range(len(vertices) // 3)]
        mesh.from_pydata(vertices, [], faces)
        mesh.materials.append(material)
        obj = bpy.data.objects.new(f"{name}.{index}", mesh)
        scene.collection.objects.link(obj)
    for index, light in enumerate(POINT_LIGHTS):  # written only with --approximate
        data = bpy.data.lights.new(f"point.{index}", "POINT")
        intensity = light["intensity"]
        data.energy = 4.0 * math.pi * max(intensity)
        data.color = tuple(i / max(intensity) for i in intensity)
        data.shadow_soft_size = 0.0
        obj = bpy.data.objects.new(f"point.{index}", data)
        obj.location = light["position"]
        scene.collection.objects.link(obj)
    _camera(scene)
)py";
}

std::string cycles_render_script() {
  return R"py("""Renders replicates of scene.py (beside this file) with Cycles; from pcbench export.

blender -b -P render.py -- --replicates R --spp N --out FOLDER [--threads T] [--first-seed S]
writes FOLDER/cycles_rep000.exr ... one 32-bit float EXR per replicate, replicate k with seed
S + k: independent renders, as pcbench verify --images needs. Exit 2 on bad arguments (FOLDER
must be new or empty), 1 when a render fails.
"""
import argparse
import os
import runpy
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="blender -b -P render.py --")
    parser.add_argument("--replicates", type=int, required=True)
    parser.add_argument("--spp", type=int, required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--first-seed", type=int, default=1)
    args = parser.parse_args(argv)
    if args.replicates < 2 or args.spp < 1 or args.threads < 0 or args.first_seed < 0:
        parser.error("--replicates >= 2, --spp >= 1, --threads >= 0, --first-seed >= 0")
    # Files of an earlier render would join this one's set: the folder is new or empty.
    if os.path.exists(args.out) and (not os.path.isdir(args.out) or os.listdir(args.out)):
        parser.error(f"--out {args.out} exists and is not an empty folder")
    return args


def main():
    args = arguments()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    runpy.run_path(os.path.join(HERE, "scene.py"))["build"](scene)
    scene.cycles.samples = args.spp
    if args.threads:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = args.threads
    os.makedirs(args.out, exist_ok=True)
    for k in range(args.replicates):
        scene.cycles.seed = args.first_seed + k
        scene.render.filepath = os.path.join(os.path.abspath(args.out), f"cycles_rep{k:03d}.exr")
        bpy.ops.render.render(write_still=True)
        print(f"render.py: replicate {k + 1}/{args.replicates}, seed {scene.cycles.seed}: "
              f"{scene.render.filepath}", flush=True)


try:
    main()
except SystemExit:
    raise
except BaseException:  # Blender would print the error and still exit 0
    import traceback

    traceback.print_exc()
    sys.exit(1)
)py";
}

}  // namespace pcbench::scene
