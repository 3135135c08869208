#!/usr/bin/env python3
"""Write assets/chair.obj: an easy chair (armchair) like the one in Breen, House & Wozny 1994, Fig. 1.

Units m, +z up, standing on z = 0, the seat facing -y. About 0.80 m wide (x), 0.85 m deep (y),
0.80 m high at the back, seat cushion top at 0.42 m.

The chair is a union of rounded boxes (legs, arms, seat frame, seat cushion, backrest, back
cushion). Each part is a closed, consistently oriented (counter-clockwise seen from outside)
triangle mesh, and the parts are separated by 2 mm gaps, so the whole file is a closed mesh whose
parts do not intersect: the signed distance of the union is the minimum over the parts, and the
pseudo-normal sign test of a mesh obstacle is valid everywhere.

Usage: python3 scripts/make_chair.py [--out PATH]   (standard library only)
"""
import argparse
import math
import os

GAP = 0.002  # m, between neighbouring parts


def axis_samples(half, radius, band_segments, flat_step):
    """Coordinates from -half to +half: cosine-spaced in the rounded bands, uniform between."""
    inner = half - radius
    band = [-inner - radius * math.cos(0.5 * math.pi * k / band_segments) for k in range(band_segments)]
    flat_segments = max(1, round(2 * inner / flat_step))
    flat = [-inner + 2 * inner * k / flat_segments for k in range(flat_segments + 1)]
    return band + flat + [-x for x in reversed(band)]


def rounded_box(lo, hi, radius, band_segments=3, flat_step=0.12):
    """Closed mesh (vertices, faces) of the box [lo, hi] with edges and corners rounded by radius."""
    centre = [0.5 * (a + b) for a, b in zip(lo, hi)]
    half = [0.5 * (b - a) for a, b in zip(lo, hi)]
    radius = min(radius, 0.999 * min(half))
    samples = [axis_samples(h, radius, band_segments, flat_step) for h in half]
    sizes = [len(s) for s in samples]
    index = {}
    vertices = []

    def vertex(ijk):
        if ijk in index:
            return index[ijk]
        p = [samples[a][ijk[a]] for a in range(3)]
        inner = [max(-(half[a] - radius), min(half[a] - radius, p[a])) for a in range(3)]
        d = [p[a] - inner[a] for a in range(3)]
        n = math.sqrt(sum(x * x for x in d))
        q = [inner[a] + radius * d[a] / n for a in range(3)]
        index[ijk] = len(vertices)
        vertices.append(tuple(centre[a] + q[a] for a in range(3)))
        return index[ijk]

    faces = []
    for axis in range(3):
        u, v = (axis + 1) % 3, (axis + 2) % 3
        for side in (0, sizes[axis] - 1):
            outward = 1 if side else -1
            for i in range(sizes[u] - 1):
                for j in range(sizes[v] - 1):
                    quad = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        ijk = [0, 0, 0]
                        ijk[axis], ijk[u], ijk[v] = side, i + di, j + dj
                        quad.append(vertex(tuple(ijk)))
                    # (u, v, axis) is right-handed: the quad above is counter-clockwise seen
                    # from +axis; reverse it on the -axis side.
                    if outward < 0:
                        quad.reverse()
                    faces.append((quad[0], quad[1], quad[2]))
                    faces.append((quad[0], quad[2], quad[3]))
    return vertices, faces


def chair_parts():
    """(name, lo, hi, rounding radius) of each part, m."""
    g = GAP
    leg_z = 0.08
    parts = []
    for sx in (-1, 1):
        for sy in (-1, 1):
            x, y = sx * 0.335, sy * 0.36
            parts.append((f"leg_{'lr'[sx > 0]}{'fb'[sy > 0]}", (x - 0.025, y - 0.025, 0.0), (x + 0.025, y + 0.025, leg_z), 0.008))
    arm_in, arm_out = 0.27, 0.40
    back_front = 0.30
    for sx, name in ((-1, "arm_left"), (1, "arm_right")):
        xs = sorted((sx * arm_in, sx * arm_out))
        parts.append((name, (xs[0], -0.425, leg_z + g), (xs[1], back_front, 0.62), 0.05))
    parts.append(("seat_frame", (-arm_in + g, -0.42, leg_z + g), (arm_in - g, back_front - g, 0.30), 0.03))
    parts.append(("seat_cushion", (-arm_in + g, -0.425, 0.30 + g), (arm_in - g, 0.20, 0.42), 0.045))
    parts.append(("backrest", (-0.40, back_front + g, leg_z + g), (0.40, 0.425, 0.80), 0.05))
    parts.append(("back_cushion", (-arm_in + g, 0.20 + g, 0.30 + g), (arm_in - g, back_front, 0.74), 0.045))
    return parts


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(here, "..", "assets", "chair.obj"), help="output OBJ file")
    args = parser.parse_args()

    lines = [
        "# woven: easy chair (Breen, House & Wozny 1994, Fig. 1), written by scripts/make_chair.py",
        "# units m, +z up, standing on z = 0, seat facing -y; closed, faces counter-clockwise from outside",
    ]
    offset = 0
    total_faces = 0
    for name, lo, hi, radius in chair_parts():
        step = 0.03 if "leg" in name else 0.12
        bands = 2 if "leg" in name else 3
        vertices, faces = rounded_box(lo, hi, radius, bands, step)
        lines.append(f"o {name}")
        lines.extend(f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in vertices)
        lines.extend(f"f {a + offset + 1} {b + offset + 1} {c + offset + 1}" for a, b, c in faces)
        offset += len(vertices)
        total_faces += len(faces)
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w", encoding="ascii") as f:
        f.write("\n".join(lines) + "\n")
    print(f"{os.path.normpath(args.out)}: {offset} vertices, {total_faces} triangles")


if __name__ == "__main__":
    main()
