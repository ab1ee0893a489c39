# Runs an exported Cycles script without Blender and prints, as JSON, the
# shader node graph it builds for each material and for the world:
#
#   python3 cycles_node_graph.py SCRIPT.py
#
# bpy and mathutils are replaced by a recorder that keeps every node, socket
# value and link the script makes; bpy.ops.render.render writes an empty
# file where the script asks for the image. The output is one JSON object:
#   {"materials": {name: graph}, "world": graph, "world_sampling": method,
#    "shading": {mesh name: {"smooth": all faces smooth, "normals": custom vertex normals or null,
#                            "auto_smooth": bool}}}
# with graph one of
#   ["Diffuse", colour, roughness]    ["Glossy", "SHARP", colour]
#   ["Glossy", distribution, colour, roughness] (GGX, MULTI_GGX)
#   ["Glass", distribution, colour, IOR, roughness]
#   ["Emission", colour, strength]    ["Background", colour, strength]
#   ["Add", graph, graph]             ["Mix", graph (factor), graph, graph]
#   ["Geometry", output name]         null (nothing linked)
# where a gray opaque colour (r = g = b, alpha 1) is written as r alone.
import json
import os
import sys
import types


class Bag:
    """An object whose unset attributes are new Bags, so that any settings path can be assigned."""

    def __getattr__(self, name):
        if name.startswith('__'):
            raise AttributeError(name)
        value = Bag()
        object.__setattr__(self, name, value)
        return value


class Socket:
    def __init__(self, node, key):
        self.node, self.key, self.default_value = node, key, None


class Sockets:
    def __init__(self, node):
        self.node, self.by_key = node, {}

    def __getitem__(self, key):
        if key not in self.by_key:
            self.by_key[key] = Socket(self.node, key)
        return self.by_key[key]


class Node(Bag):
    def __init__(self, kind):
        object.__setattr__(self, 'kind', kind)
        object.__setattr__(self, 'inputs', Sockets(self))
        object.__setattr__(self, 'outputs', Sockets(self))


class Nodes(list):
    def new(self, kind):
        node = Node(kind)
        self.append(node)
        return node

    def __getitem__(self, key):
        if isinstance(key, str):
            return next(n for n in self if n.kind == key)
        return list.__getitem__(self, key)


class Links(list):
    def new(self, from_socket, to_socket):
        self.append((from_socket, to_socket))


class NodeTree:
    def __init__(self):
        self.nodes, self.links = Nodes(), Links()


class Collection(list):
    def __init__(self, make):
        super().__init__()
        self.make = make

    def new(self, name, *args):
        item = self.make(name, *args)
        self.append(item)
        return item


def new_material(name):
    m = Bag()
    m.name, m.node_tree = name, NodeTree()
    return m


def new_world(name):
    w = Bag()
    w.name, w.node_tree = name, NodeTree()
    w.node_tree.nodes.append(Node('Background'))  # a new world's tree holds a Background node
    return w


def new_mesh(name):
    mesh = Bag()
    mesh.name, mesh.materials, mesh.polygons, mesh.custom_normals = name, [], [], None
    mesh.from_pydata = lambda vertices, edges, faces: mesh.polygons.extend(Bag() for _ in faces)
    mesh.update = lambda: None

    def set_normals(normals):
        mesh.custom_normals = [list(n) for n in normals]
    mesh.normals_split_custom_set_from_vertices = set_normals
    return mesh


class Vector(tuple):
    def __new__(cls, values):
        return tuple.__new__(cls, values)

    def __sub__(self, other):
        return Vector(a - b for a, b in zip(self, other))

    def normalized(self):
        length = sum(a * a for a in self) ** 0.5
        return Vector(a / length for a in self)


def new_object(name, data):
    o = Bag()
    o.name, o.data = name, data
    return o


def new_bag(name):
    b = Bag()
    b.name = name
    return b


scene = Bag()
scene.collection.objects.link = lambda o: None
scene.view_layers = [Bag()]
data = types.SimpleNamespace(objects=Collection(new_object), meshes=Collection(new_mesh),
                             cameras=Collection(new_bag), lights=Collection(new_bag),
                             materials=Collection(new_material), worlds=Collection(new_world))


def render(write_still):
    with open(scene.render.filepath, 'wb'):
        pass


bpy = types.ModuleType('bpy')
bpy.data, bpy.context = data, types.SimpleNamespace(scene=scene)
bpy.ops = types.SimpleNamespace(render=types.SimpleNamespace(render=render))
mathutils = types.ModuleType('mathutils')
mathutils.Matrix = lambda rows: rows
mathutils.Vector = Vector
sys.modules['bpy'], sys.modules['mathutils'] = bpy, mathutils


def colour(value):
    r, g, b, a = value
    return r if r == g == b and a == 1 else list(value)


def graph(tree, socket):
    """The graph of whatever is linked into the input `socket`."""
    sources = [f for f, t in tree.links if t is socket]
    if not sources:
        return None
    source = sources[0]
    n = source.node
    inputs = n.inputs
    if n.kind == 'ShaderNodeBsdfDiffuse':
        return ['Diffuse', colour(inputs['Color'].default_value), inputs['Roughness'].default_value]
    if n.kind == 'ShaderNodeBsdfGlossy':
        if n.distribution == 'SHARP':
            return ['Glossy', n.distribution, colour(inputs['Color'].default_value)]
        return ['Glossy', n.distribution, colour(inputs['Color'].default_value), inputs['Roughness'].default_value]
    if n.kind == 'ShaderNodeBsdfGlass':
        return ['Glass', n.distribution, colour(inputs['Color'].default_value), inputs['IOR'].default_value,
                inputs['Roughness'].default_value]
    if n.kind == 'ShaderNodeEmission':
        return ['Emission', colour(inputs['Color'].default_value), inputs['Strength'].default_value]
    if n.kind == 'ShaderNodeAddShader':
        return ['Add', graph(tree, inputs[0]), graph(tree, inputs[1])]
    if n.kind == 'ShaderNodeMixShader':
        return ['Mix', graph(tree, inputs['Fac']), graph(tree, inputs[1]), graph(tree, inputs[2])]
    if n.kind == 'ShaderNodeNewGeometry':
        return ['Geometry', source.key]
    return ['unknown node', n.kind]


def main():
    script = sys.argv[1]
    output = os.path.join(os.path.dirname(os.path.abspath(script)), 'node_graph_render.exr')
    sys.argv = ['blender', '--', '--seed', '1', '--output', output]
    with open(script) as f:
        code = compile(f.read(), script, 'exec')
    exec(code, {'__name__': '__main__'})
    materials = {}
    for m in data.materials:
        outputs = [n for n in m.node_tree.nodes if n.kind == 'ShaderNodeOutputMaterial']
        materials[m.name] = graph(m.node_tree, outputs[0].inputs['Surface']) if len(outputs) == 1 else None
    background = data.worlds[0].node_tree.nodes['Background']
    world = ['Background', colour(background.inputs['Color'].default_value),
             background.inputs['Strength'].default_value]
    # Per mesh: whether every face is smooth-shaded, and its custom vertex normals (null when none).
    shading = {m.name: {'smooth': bool(m.polygons) and all(p.use_smooth is True for p in m.polygons),
                        'normals': m.custom_normals, 'auto_smooth': m.use_auto_smooth is True}
               for m in data.meshes}
    print(json.dumps({'materials': materials, 'world': world, 'shading': shading,
                      'world_sampling': data.worlds[0].cycles.sampling_method}))


main()
