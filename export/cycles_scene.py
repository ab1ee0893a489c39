# The Blender program of `furnace export --format cycles`. export/cycles.cpp
# writes a script that opens with comments stating the facts about Cycles it
# relies on and each shape's tessellation error, then the data this program
# reads, decided by the exporter (no material or shape is decided here):
#   SCENE     {'name', 'spp', 'resolution': (x, y), 'pixel_aspect': (x, y),
#              'camera': {'matrix', 'ortho_scale', 'sensor_fit', 'clip_start', 'clip_end'},
#              'environment': radiance, 'world_light_sampling': False turns off sampling the world
#              as a light, 'max_bounces',
#              'objects': [{'name', 'albedo', 'mirror': Glossy SHARP if True,
#                           'ggx': None, or (distribution, roughness) for a Glossy BSDF of that
#                                  distribution ('GGX' or 'MULTI_GGX') and roughness,
#                           'glass': None, or (distribution, IOR, roughness) for a Glass BSDF
#                                  ('SHARP' as exported),
#                           else Diffuse,
#                           'emission', 'two_sided',
#                           'smooth_about': None (flat shading), or a centre: smooth shading with
#                                  the unit normal from that centre at each vertex (a sphere's own),
#                           'vertices', 'triangles'}]}
#   FILTER    (Cycles' pixel filter type, its width in pixels)
#   SEED_MAX, SPP_MAX   Blender's limits of scene.cycles.seed and .samples
# and then everything below the marker line, byte for byte: the build embeds
# it (export/embed_text.cmake); this preamble is not written. Alone this file
# only compiles (ctest export.CyclesScenePy.Compiles): the names above are
# defined by the exported script.
# ---- furnace embeds everything below this line ----

import argparse
import os
import sys
import time

import bpy
from mathutils import Matrix, Vector


def arguments():
    argv = sys.argv[sys.argv.index('--') + 1:] if '--' in sys.argv else []
    parser = argparse.ArgumentParser(
        prog='blender -b --factory-startup --python-exit-code 1 --python SCRIPT --',
        description='Render scene ' + SCENE['name'] + ' with Cycles for furnace check.')
    seeds = parser.add_mutually_exclusive_group(required=True)
    seeds.add_argument('--seed', type=int, help='one render with this seed')
    seeds.add_argument('--seeds', help='A-B: one render per seed A..B (inclusive) in this Blender process')
    parser.add_argument('--output', required=True, help='EXR path; with --seeds it must contain {seed}')
    parser.add_argument('--spp', type=int, default=SCENE['spp'], help='samples per pixel')
    parser.add_argument('--threads', type=int, default=0, help='Cycles threads (0: all cores)')
    args = parser.parse_args(argv)
    if args.seed is not None:
        seeds = [args.seed]
    else:
        parts = args.seeds.split('-')
        if len(parts) != 2 or not all(p.isdigit() for p in parts) or int(parts[0]) > int(parts[1]):
            parser.error('--seeds must be A-B with integers 0 <= A <= B, got %r' % args.seeds)
        seeds = list(range(int(parts[0]), int(parts[1]) + 1))
        if '{seed}' not in args.output:
            parser.error('--output must contain {seed} when --seeds names several renders, got %r' % args.output)
    for s in seeds:
        if not 0 <= s <= SEED_MAX:
            parser.error('seed %d is outside Cycles\' range 0..%d' % (s, SEED_MAX))
    if not 1 <= args.spp <= SPP_MAX:
        parser.error('--spp must be in 1..%d, got %d' % (SPP_MAX, args.spp))
    if not 0 <= args.threads <= 1024:
        parser.error('--threads must be in 0..1024, got %d' % args.threads)
    directory = os.path.dirname(os.path.abspath(args.output))
    if not os.path.isdir(directory) or not os.access(directory, os.W_OK):
        parser.error('--output %r: the directory %r does not exist or is not writable' % (args.output, directory))
    return seeds, args.output, args.spp, args.threads


def clear_file():
    for collection in (bpy.data.objects, bpy.data.meshes, bpy.data.cameras, bpy.data.lights,
                       bpy.data.materials, bpy.data.worlds):
        for item in list(collection):
            collection.remove(item)


def material(o):
    m = bpy.data.materials.new(o['name'])
    m.use_nodes = True
    nodes, links = m.node_tree.nodes, m.node_tree.links
    nodes.clear()
    output = nodes.new('ShaderNodeOutputMaterial')
    output.target = 'CYCLES'
    rho = o['albedo']
    surface = None
    if rho > 0 or o['emission'] == 0:
        if o['mirror']:
            bsdf = nodes.new('ShaderNodeBsdfGlossy')
            bsdf.distribution = 'SHARP'
        elif o['ggx'] is not None:
            bsdf = nodes.new('ShaderNodeBsdfGlossy')
            bsdf.distribution = o['ggx'][0]
            bsdf.inputs['Roughness'].default_value = o['ggx'][1]
        elif o['glass'] is not None:
            # Every input set: Blender 3.x creates a Glass node as Beckmann of IOR 1.45.
            bsdf = nodes.new('ShaderNodeBsdfGlass')
            bsdf.distribution = o['glass'][0]
            bsdf.inputs['IOR'].default_value = o['glass'][1]
            bsdf.inputs['Roughness'].default_value = o['glass'][2]
        else:
            bsdf = nodes.new('ShaderNodeBsdfDiffuse')
            bsdf.inputs['Roughness'].default_value = 0.0
        bsdf.inputs['Color'].default_value = (rho, rho, rho, 1.0)
        surface = bsdf.outputs[0]
    if o['emission'] > 0:
        emission = nodes.new('ShaderNodeEmission')
        emission.inputs['Color'].default_value = (1.0, 1.0, 1.0, 1.0)
        emission.inputs['Strength'].default_value = o['emission']
        emitted = emission.outputs[0]
        if not o['two_sided']:
            geometry = nodes.new('ShaderNodeNewGeometry')
            front_only = nodes.new('ShaderNodeMixShader')
            links.new(geometry.outputs['Backfacing'], front_only.inputs['Fac'])
            links.new(emitted, front_only.inputs[1])  # input 2 (back faces) stays empty: no emission
            emitted = front_only.outputs[0]
        if surface is None:
            surface = emitted
        else:
            both = nodes.new('ShaderNodeAddShader')
            links.new(surface, both.inputs[0])
            links.new(emitted, both.inputs[1])
            surface = both.outputs[0]
    links.new(surface, output.inputs['Surface'])
    return m


def build(spp, threads):
    clear_file()
    scene = bpy.context.scene
    for o in SCENE['objects']:
        mesh = bpy.data.meshes.new(o['name'])
        mesh.from_pydata(o['vertices'], [], o['triangles'])
        mesh.update()
        if o['smooth_about'] is not None:
            centre = Vector(o['smooth_about'])
            mesh.use_auto_smooth = True
            for polygon in mesh.polygons:
                polygon.use_smooth = True
            mesh.normals_split_custom_set_from_vertices([tuple((Vector(v) - centre).normalized())
                                                         for v in o['vertices']])
        mesh.materials.append(material(o))
        scene.collection.objects.link(bpy.data.objects.new(o['name'], mesh))

    world = bpy.data.worlds.new('environment')
    world.use_nodes = True
    background = world.node_tree.nodes['Background']
    background.inputs['Color'].default_value = (1.0, 1.0, 1.0, 1.0)
    background.inputs['Strength'].default_value = SCENE['environment']
    world.cycles.sampling_method = 'AUTOMATIC' if SCENE['world_light_sampling'] else 'NONE'
    scene.world = world

    c = SCENE['camera']
    camera = bpy.data.cameras.new('camera')
    camera.type = 'ORTHO'
    camera.ortho_scale = c['ortho_scale']
    camera.sensor_fit = c['sensor_fit']
    camera.clip_start = c['clip_start']
    camera.clip_end = c['clip_end']
    camera_object = bpy.data.objects.new('camera', camera)
    camera_object.matrix_world = Matrix(c['matrix'])
    scene.collection.objects.link(camera_object)
    scene.camera = camera_object

    r = scene.render
    r.engine = 'CYCLES'
    r.resolution_x, r.resolution_y = SCENE['resolution']
    r.resolution_percentage = 100
    r.pixel_aspect_x, r.pixel_aspect_y = SCENE['pixel_aspect']
    r.use_border = False
    r.film_transparent = False
    r.use_compositing = False
    r.use_sequencer = False
    r.dither_intensity = 0.0
    r.use_persistent_data = True
    r.threads_mode = 'FIXED' if threads > 0 else 'AUTO'
    if threads > 0:
        r.threads = threads
    r.use_file_extension = False
    image = r.image_settings
    image.file_format = 'OPEN_EXR'
    image.color_mode = 'RGB'
    image.color_depth = '32'
    image.exr_codec = 'ZIP'
    image.use_preview = False
    view = scene.view_settings
    view.view_transform = 'Standard'
    view.look = 'None'
    view.exposure = 0.0
    view.gamma = 1.0
    view.use_curve_mapping = False

    cy = scene.cycles
    cy.device = 'CPU'
    cy.samples = spp
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.time_limit = 0.0
    cy.sampling_pattern = 'SOBOL'
    cy.scrambling_distance = 1.0
    cy.auto_scrambling_distance = False
    cy.use_animated_seed = False
    cy.sample_offset = 0
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.light_sampling_threshold = 0.0
    cy.caustics_reflective = True
    cy.caustics_refractive = True
    cy.blur_glossy = 0.0
    cy.use_guiding = False
    cy.use_fast_gi = False
    cy.use_camera_cull = False
    cy.use_distance_cull = False
    cy.direct_light_sampling_type = 'MULTIPLE_IMPORTANCE_SAMPLING'
    bounces = SCENE['max_bounces']
    cy.max_bounces = bounces
    cy.diffuse_bounces = bounces
    cy.glossy_bounces = bounces
    cy.transmission_bounces = bounces
    cy.transparent_max_bounces = bounces
    cy.volume_bounces = 0
    cy.min_light_bounces = 0
    cy.min_transparent_bounces = 0
    cy.pixel_filter_type = FILTER[0]
    cy.filter_width = FILTER[1]
    cy.film_exposure = 1.0
    for layer in scene.view_layers:
        layer.samples = 0
        layer.cycles.denoising_store_passes = False
    return scene


def render(scene, seed, path):
    scene.cycles.seed = seed
    temporary = os.path.join(os.path.dirname(os.path.abspath(path)), '.' + os.path.basename(path) + '.tmp.exr')
    scene.render.filepath = temporary
    start = time.time()
    bpy.ops.render.render(write_still=True)
    if not os.path.isfile(temporary):
        raise RuntimeError('Blender wrote no image to ' + temporary)
    os.replace(temporary, path)
    print('furnace-cycles: seed %d -> %s (%.2f s)' % (seed, path, time.time() - start), flush=True)


def main():
    seeds, output, spp, threads = arguments()
    scene = build(spp, threads)
    for seed in seeds:
        render(scene, seed, output.replace('{seed}', str(seed)))


main()
