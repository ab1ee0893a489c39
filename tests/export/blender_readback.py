# Runs inside Blender: builds the scene of an exported Cycles script (its
# build(), without rendering) and prints what Blender made of it, as one line
# "FURNACE-READBACK {json}":
#   blender -b --factory-startup --python-exit-code 1 --python blender_readback.py -- SCRIPT.py
# camera: render resolution and pixel aspect, the camera's type, sensor fit,
# ortho_scale, clip_start, shift, matrix_world (rows) and view_frame(scene),
# the image frame's four corners in camera space as Blender computes them
# from all of those (camera_readback_test.cpp turns them into each pixel's
# ray); materials: for each object, its material's links as
# [from node type, from socket, to node type, to socket index]; faces: for
# each object, every polygon's [normal, centre] in world space as Blender
# orients it (the side Cycles' Backfacing calls front).
import json
import sys

import bpy

script = sys.argv[sys.argv.index('--') + 1]
source = open(script).read().rstrip()
if not source.endswith('\nmain()'):
    raise SystemExit('the exported script %s no longer ends with main()' % script)
namespace = {'__name__': 'furnace_readback'}
exec(compile(source[:-len('main()')], script, 'exec'), namespace)
scene = namespace['build'](1, 1)
camera = scene.camera


def socket_index(socket):
    return [i for i, s in enumerate(socket.node.inputs) if s == socket][0]


materials, faces = {}, {}
for obj in scene.objects:
    if obj.type != 'MESH':
        continue
    tree = obj.data.materials[0].node_tree
    materials[obj.name] = [[l.from_node.type, l.from_socket.name, l.to_node.type, socket_index(l.to_socket)]
                           for l in tree.links]
    rotation = obj.matrix_world.to_3x3()
    faces[obj.name] = [[list((rotation @ p.normal).normalized()), list(obj.matrix_world @ p.center)]
                       for p in obj.data.polygons]
out = {
    'resolution': [scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage],
    'pixel_aspect': [scene.render.pixel_aspect_x, scene.render.pixel_aspect_y],
    'type': camera.data.type,
    'sensor_fit': camera.data.sensor_fit,
    'ortho_scale': camera.data.ortho_scale,
    'clip_start': camera.data.clip_start,
    'shift': [camera.data.shift_x, camera.data.shift_y],
    'matrix_world': [list(row) for row in camera.matrix_world],
    'frame': [list(v) for v in camera.data.view_frame(scene=scene)],
    'materials': materials,
    'faces': faces,
}
print('FURNACE-READBACK ' + json.dumps(out), flush=True)
