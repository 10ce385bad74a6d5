#!/usr/bin/env python3
"""Hand-made glTF files per material extension, in the style of Khronos' Compare* assets (issue 34).

Each case is a row of five spheres varying one parameter of one extension, with and without a
texture, written twice:

  OUT/<case>.gltf   the glTF file (one UV sphere mesh in <case>.bin, five nodes along x, five
                    materials, and for textured cases a PNG beside it)
  OUT/<case>.json   a luz scene that draws the glTF file, lit and framed for `luz render`
  OUT/<case>.luz.json
                    the same five materials in luz's own scene format (the extensions' names on
                    metal_rough), on luz spheres at the same places

tests/gltf.rs (`generated_compare_files_equal_their_json`) loads both and asserts that every
material (and every map) of the glTF file equals its luz-JSON twin. Standard library only.

    python3 scripts/gltf_compare.py OUT_DIR
"""

import json
import math
import os
import struct
import sys
import zlib

# (case, extension, glTF key, luz block, luz key, five values, texture slot or None).
# Every value goes into both files: the glTF extension object and luz's block of the same name.
CASES = [
    ("clearcoat", "KHR_materials_clearcoat", "clearcoatFactor", "clearcoat", "clearcoatFactor",
     [0.0, 0.25, 0.5, 0.75, 1.0], None),
    ("clearcoat_roughness", "KHR_materials_clearcoat", "clearcoatRoughnessFactor", "clearcoat",
     "clearcoatRoughnessFactor", [0.0, 0.25, 0.5, 0.75, 1.0], None),
    ("sheen_roughness", "KHR_materials_sheen", "sheenRoughnessFactor", "sheen",
     "sheenRoughnessFactor", [0.0, 0.25, 0.5, 0.75, 1.0], None),
    ("sheen_color", "KHR_materials_sheen", "sheenColorFactor", "sheen", "sheenColorFactor",
     [[0, 0, 0], [0.25, 0.1, 0.1], [0.5, 0.2, 0.2], [0.75, 0.3, 0.3], [1, 0.4, 0.4]], None),
    ("transmission", "KHR_materials_transmission", "transmissionFactor", "transmission",
     "transmissionFactor", [0.0, 0.25, 0.5, 0.75, 1.0], None),
    ("transmission_texture", "KHR_materials_transmission", "transmissionFactor", "transmission",
     "transmissionFactor", [0.2, 0.4, 0.6, 0.8, 1.0], ("transmissionTexture", "transmission", None)),
    ("volume_thickness", "KHR_materials_volume", "thicknessFactor", "volume", "thicknessFactor",
     [0.0, 0.5, 1.0, 1.5, 2.0], ("thicknessTexture", "thickness", "g")),
    ("volume_attenuation", "KHR_materials_volume", "attenuationDistance", "volume",
     "attenuationDistance", [0.25, 0.5, 1.0, 2.0, 4.0], None),
    ("dispersion", "KHR_materials_dispersion", "dispersion", "dispersion", "dispersion",
     [0.0, 0.5, 1.0, 2.0, 4.0], None),
    ("ior", "KHR_materials_ior", "ior", "ior", "ior", [1.0, 1.33, 1.5, 2.0, 2.5], None),
    ("specular", "KHR_materials_specular", "specularFactor", "specular", "specularFactor",
     [0.0, 0.25, 0.5, 0.75, 1.0], None),
    ("specular_color", "KHR_materials_specular", "specularColorFactor", "specular",
     "specularColorFactor", [[1, 1, 1], [1, 0.5, 0.5], [0.5, 1, 0.5], [0.5, 0.5, 1], [2, 2, 2]],
     None),
    ("diffuse_transmission", "KHR_materials_diffuse_transmission", "diffuseTransmissionFactor",
     "diffuse_transmission", "diffuseTransmissionFactor", [0.0, 0.25, 0.5, 0.75, 1.0],
     ("diffuseTransmissionTexture", "diffuse_transmission", "a")),
    # The layers' textures, each multiplying its factor (the channel glTF reads: R unless given).
    ("clearcoat_texture", "KHR_materials_clearcoat", "clearcoatFactor", "clearcoat",
     "clearcoatFactor", [0.2, 0.4, 0.6, 0.8, 1.0], ("clearcoatTexture", "clearcoat", None)),
    ("clearcoat_normal_texture", "KHR_materials_clearcoat", "clearcoatFactor", "clearcoat",
     "clearcoatFactor", [0.2, 0.4, 0.6, 0.8, 1.0], ("clearcoatNormalTexture", "clearcoat_normal", None)),
    ("clearcoat_roughness_texture", "KHR_materials_clearcoat", "clearcoatRoughnessFactor",
     "clearcoat", "clearcoatRoughnessFactor", [0.2, 0.4, 0.6, 0.8, 1.0],
     ("clearcoatRoughnessTexture", "clearcoat_roughness", "g")),
    ("sheen_color_texture", "KHR_materials_sheen", "sheenColorFactor", "sheen", "sheenColorFactor",
     [[0.2, 0.2, 0.2], [0.4, 0.3, 0.3], [0.6, 0.4, 0.4], [0.8, 0.5, 0.5], [1, 0.6, 0.6]],
     ("sheenColorTexture", "sheen_color", None)),
    ("sheen_roughness_texture", "KHR_materials_sheen", "sheenRoughnessFactor", "sheen",
     "sheenRoughnessFactor", [0.2, 0.4, 0.6, 0.8, 1.0],
     ("sheenRoughnessTexture", "sheen_roughness", "a")),
    ("specular_texture", "KHR_materials_specular", "specularFactor", "specular",
     "specularFactor", [0.2, 0.4, 0.6, 0.8, 1.0], ("specularTexture", "specular_factor", "a")),
    ("specular_color_texture", "KHR_materials_specular", "specularColorFactor", "specular",
     "specularColorFactor", [[1, 1, 1], [1, 0.5, 0.5], [0.5, 1, 0.5], [0.5, 0.5, 1], [2, 2, 2]],
     ("specularColorTexture", "specular_color", None)),
    ("anisotropy", "KHR_materials_anisotropy", "anisotropyStrength", "anisotropy",
     "anisotropyStrength", [0.0, 0.25, 0.5, 0.75, 1.0], None),
    ("anisotropy_rotation", "KHR_materials_anisotropy", "anisotropyRotation", "anisotropy",
     "anisotropyRotation", [0.0, 0.4, 0.8, 1.2, 1.6], None),
    ("anisotropy_texture", "KHR_materials_anisotropy", "anisotropyStrength", "anisotropy",
     "anisotropyStrength", [0.2, 0.4, 0.6, 0.8, 1.0], ("anisotropyTexture", "anisotropy", None)),
    ("iridescence", "KHR_materials_iridescence", "iridescenceFactor", "iridescence",
     "iridescenceFactor", [0.0, 0.25, 0.5, 0.75, 1.0], None),
    ("iridescence_ior", "KHR_materials_iridescence", "iridescenceIor", "iridescence",
     "iridescenceIor", [1.0, 1.2, 1.4, 1.6, 1.8], None),
    ("iridescence_texture", "KHR_materials_iridescence", "iridescenceFactor", "iridescence",
     "iridescenceFactor", [0.2, 0.4, 0.6, 0.8, 1.0], ("iridescenceTexture", "iridescence", None)),
    ("iridescence_thickness", "KHR_materials_iridescence", "iridescenceThicknessMaximum",
     "iridescence", "iridescenceThicknessMaximum", [200, 350, 500, 650, 800],
     ("iridescenceThicknessTexture", "iridescence_thickness", "g")),
]

# Fields a case needs beside its varied one (the glass cases need a transmission to show).
EXTRA = {
    "volume_thickness": {"KHR_materials_transmission": {"transmissionFactor": 1}},
    "volume_attenuation": {
        "KHR_materials_transmission": {"transmissionFactor": 1},
        "KHR_materials_volume": {"thicknessFactor": 1, "attenuationColor": [0.9, 0.5, 0.3]},
    },
    "dispersion": {
        "KHR_materials_transmission": {"transmissionFactor": 1},
        "KHR_materials_volume": {"thicknessFactor": 1},
    },
    "clearcoat_roughness_texture": {"KHR_materials_clearcoat": {"clearcoatFactor": 1}},
    "sheen_roughness_texture": {"KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1]}},
    "anisotropy_rotation": {"KHR_materials_anisotropy": {"anisotropyStrength": 0.8}},
    "iridescence_ior": {"KHR_materials_iridescence": {"iridescenceFactor": 1}},
    "iridescence_thickness": {
        "KHR_materials_iridescence": {"iridescenceFactor": 1, "iridescenceThicknessMinimum": 100},
    },
}

# glTF extension name → luz block name.
LUZ_BLOCK = {
    "KHR_materials_clearcoat": "clearcoat",
    "KHR_materials_sheen": "sheen",
    "KHR_materials_transmission": "transmission",
    "KHR_materials_volume": "volume",
    "KHR_materials_dispersion": "dispersion",
    "KHR_materials_diffuse_transmission": "diffuse_transmission",
    "KHR_materials_ior": "ior",
    "KHR_materials_specular": "specular",
    "KHR_materials_anisotropy": "anisotropy",
    "KHR_materials_iridescence": "iridescence",
}

SPACING = 2.5


def sphere(rings=24, segments=48):
    """A UV sphere of radius 1: interleaved positions and normals, UVs, u32 indices."""
    pos, uv, idx = [], [], []
    for i in range(rings + 1):
        v = i / rings
        theta = v * math.pi
        for j in range(segments + 1):
            u = j / segments
            phi = u * 2.0 * math.pi
            pos.append((math.sin(theta) * math.cos(phi), math.cos(theta),
                        -math.sin(theta) * math.sin(phi)))
            uv.append((u, v))
    row = segments + 1
    for i in range(rings):
        for j in range(segments):
            a, b = i * row + j, (i + 1) * row + j
            idx += [a, b, a + 1, a + 1, b, b + 1]
    return pos, uv, idx


def png(width, height, pixel):
    """An 8-bit RGBA PNG; pixel(x, y) -> (r, g, b, a)."""
    raw = b"".join(
        b"\0" + bytes(c for x in range(width) for c in pixel(x, y)) for y in range(height))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    header = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def write_case(out, case, ext, key, block, luz_key, values, texture):
    pos, uv, idx = sphere()
    bin_data = b"".join(struct.pack("<3f", *p) for p in pos)
    normals_at = len(bin_data)
    bin_data += b"".join(struct.pack("<3f", *p) for p in pos)
    uv_at = len(bin_data)
    bin_data += b"".join(struct.pack("<2f", *t) for t in uv)
    idx_at = len(bin_data)
    bin_data += struct.pack(f"<{len(idx)}I", *idx)
    with open(os.path.join(out, f"{case}.bin"), "wb") as f:
        f.write(bin_data)
    n = len(pos)
    doc = {
        "asset": {"version": "2.0", "generator": "luz scripts/gltf_compare.py"},
        "buffers": [{"uri": f"{case}.bin", "byteLength": len(bin_data)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 12 * n},
            {"buffer": 0, "byteOffset": normals_at, "byteLength": 12 * n},
            {"buffer": 0, "byteOffset": uv_at, "byteLength": 8 * n},
            {"buffer": 0, "byteOffset": idx_at, "byteLength": 4 * len(idx)},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
             "min": [-1, -1, -1], "max": [1, 1, 1]},
            {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": n, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5125, "count": len(idx), "type": "SCALAR"},
        ],
        "extensionsUsed": sorted({ext, *EXTRA.get(case, {}).keys()}),
        "materials": [],
        "meshes": [],
        "nodes": [],
        "scenes": [{"nodes": list(range(len(values)))}],
        "scene": 0,
    }
    luz_materials = {}
    if texture:
        # Stripes: a ramp 0 → 255 across u, in every channel (the map's channel is read).
        # A normal map instead: tilts growing across u from the flat (128, 128, 255).
        pixel = ((lambda x, y: (128 + x * 8, 128, 255, 255)) if texture[1].endswith("normal")
                 else (lambda x, y: (x * 36, x * 36, x * 36, x * 36)))
        with open(os.path.join(out, f"{case}.png"), "wb") as f:
            f.write(png(8, 2, pixel))
        doc["images"] = [{"uri": f"{case}.png"}]
        doc["textures"] = [{"source": 0}]
    for i, value in enumerate(values):
        exts = json.loads(json.dumps(EXTRA.get(case, {})))
        exts.setdefault(ext, {})[key] = value
        if texture:
            exts[ext][texture[0]] = {"index": 0}
        name = f"{case}_{i}"
        doc["materials"].append({
            "name": name,
            "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1],
                                     "metallicFactor": 0.0, "roughnessFactor": 0.4},
            "extensions": exts,
        })
        doc["meshes"].append({"primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
            "indices": 3, "material": i}]})
        x = (i - (len(values) - 1) / 2) * SPACING
        doc["nodes"].append({"name": name, "mesh": i, "translation": [x, 0, 0]})
        m = {"model": "metal_rough", "base_color": [0.8, 0.8, 0.8], "metallic": 0,
             "roughness": 0.4}
        for e, fields in exts.items():
            fields = {k: v for k, v in fields.items() if not k.endswith("Texture")}
            m[LUZ_BLOCK[e]] = fields
        if texture:
            slot, channel = texture[1], texture[2]
            m["textures"] = {slot: (f"{case}.png" if channel is None
                                    else {"path": f"{case}.png", "channel": channel})}
        luz_materials[name] = m
    with open(os.path.join(out, f"{case}.gltf"), "w") as f:
        json.dump(doc, f, indent=1)
    width = len(values) * SPACING + 1
    common = {
        "camera": {"position": [0, 1, width * 0.45], "target": [0, 0, 0], "fov_y_deg": 45},
        "output": {"width": 800, "height": 240},
        "lights": [{"type": "directional", "direction": [-0.3, -1, -0.6], "intensity": 3}],
        "environment": {"uniform": [0.3, 0.35, 0.4]},
    }
    with open(os.path.join(out, f"{case}.json"), "w") as f:
        json.dump({**common, "objects": [{"mesh": {"type": "gltf", "path": f"{case}.gltf"}}]},
                  f, indent=1)
    objects = [{"name": name, "mesh": {"type": "sphere", "radius": 1, "segments": 48, "rings": 24}, "material": name,
                "position": [(i - (len(values) - 1) / 2) * SPACING, 0, 0]}
               for i, name in enumerate(luz_materials)]
    with open(os.path.join(out, f"{case}.luz.json"), "w") as f:
        json.dump({**common, "materials": luz_materials, "objects": objects}, f, indent=1)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    for case in CASES:
        write_case(out, *case)
    print(f"wrote {len(CASES)} cases to {out}: " + ", ".join(c[0] for c in CASES))


if __name__ == "__main__":
    main()
