"""Writes small glTF scenes for the tests: axis-aligned quads seen by an orthographic camera
whose pixels are one world unit wide, so that every quad covers a known block of pixels (or a
perspective camera at the same place, for quads of any shape)."""

import base64
import json
import struct
from pathlib import Path


class QuadScene:
    """Quads facing +Z in front of an orthographic camera at z = 10 looking down -Z. The image
    is width x height pixels, one world unit each, centred on the origin: the quad spanning
    pixel columns [x0, x1) and rows [y0, y1) (rows top first) is add_quad(x0, y0, x1, y1)."""

    def __init__(self, width, height, perspective_yfov=None):
        self.width, self.height = width, height
        self.perspective_yfov = perspective_yfov  # radians: a perspective camera instead
        self.quads = []  # (4 world corners, node name, mesh name, class or None, material)
        self.materials = []

    def material(self, name, color=(0.8, 0.8, 0.8, 1.0), double_sided=False, alpha_mode=None,
                 alpha_cutoff=None):
        material = {"name": name, "doubleSided": double_sided, "pbrMetallicRoughness": {
            "baseColorFactor": list(color), "metallicFactor": 0.0}}
        if alpha_mode is not None:
            material["alphaMode"] = alpha_mode
        if alpha_cutoff is not None:
            material["alphaCutoff"] = alpha_cutoff
        self.materials.append(material)
        return len(self.materials) - 1

    def add_quad(self, x0, y0, x1, y1, z=0.0, node=None, mesh=None, cls=None, material=None):
        # World x = column - w/2, world y = h/2 - row.
        left, right = x0 - self.width / 2, x1 - self.width / 2
        top, bottom = self.height / 2 - y0, self.height / 2 - y1
        corners = [(left, bottom, z), (right, bottom, z), (right, top, z), (left, top, z)]
        self.add_corners(corners, node, mesh, cls, material)

    def add_corners(self, corners, node=None, mesh=None, cls=None, material=None):
        """A quad with any 4 world corners, counter-clockwise seen from its front."""
        self.quads.append((corners, node, mesh, cls, material))

    def write(self, path):
        w, h = self.width, self.height
        blob = bytearray()
        accessors, views, meshes, nodes = [], [], [], []
        for i, (positions, node, mesh, cls, material) in enumerate(self.quads):
            pos_offset = len(blob)
            for p in positions:
                blob += struct.pack("<3f", *p)
            idx_offset = len(blob)
            blob += struct.pack("<6H", 0, 1, 2, 0, 2, 3)
            while len(blob) % 4:
                blob += b"\0"
            views.append({"buffer": 0, "byteOffset": pos_offset, "byteLength": 48})
            views.append({"buffer": 0, "byteOffset": idx_offset, "byteLength": 12})
            accessors.append({"bufferView": 2 * i, "componentType": 5126, "count": 4,
                              "type": "VEC3", "min": [min(p[k] for p in positions) for k in range(3)],
                              "max": [max(p[k] for p in positions) for k in range(3)]})
            accessors.append({"bufferView": 2 * i + 1, "componentType": 5123, "count": 6,
                              "type": "SCALAR"})
            primitive = {"attributes": {"POSITION": 2 * i}, "indices": 2 * i + 1}
            if material is not None:
                primitive["material"] = material
            entry = {"primitives": [primitive]}
            if mesh is not None:
                entry["name"] = mesh
            meshes.append(entry)
            n = {"mesh": i}
            if node is not None:
                n["name"] = node
            if cls is not None:
                n["extras"] = {"class": cls}
            nodes.append(n)
        nodes.append({"camera": 0, "translation": [0, 0, 10], "name": "camera"})
        gltf = {
            "asset": {"version": "2.0"},
            "scene": 0,
            "scenes": [{"nodes": list(range(len(nodes)))}],
            "nodes": nodes,
            "meshes": meshes,
            "accessors": accessors,
            "bufferViews": views,
            "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64,"
                         + base64.b64encode(bytes(blob)).decode()}],
            "cameras": [{"type": "orthographic", "orthographic": {
                "xmag": w / 2, "ymag": h / 2, "znear": 0.5, "zfar": 100.0}}
                if self.perspective_yfov is None else {"type": "perspective", "perspective": {
                    "yfov": self.perspective_yfov, "aspectRatio": w / h, "znear": 0.5}}],
        }
        if self.materials:
            gltf["materials"] = self.materials
        Path(path).write_text(json.dumps(gltf, indent=1))
        return Path(path)
