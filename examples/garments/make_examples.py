#!/usr/bin/env python3
"""Writes the example garment files of this folder (docs/GARMENT-FORMAT.md): a circular skirt,
a four-gore A-line skirt on the straight grain and on the bias, a straight tube skirt. All on
the built-in dress form (waist 68 cm, hip 94 cm, waist 104 cm above the floor), in silk; run
them in another fabric with `woven garment FILE --fabric denim`."""
import math
import pathlib

HERE = pathlib.Path(__file__).parent
BODY = """[body]
form = "dress-form"
bust_cm = 88
waist_cm = 68
hip_cm = 94
waist_height_cm = 104
hip_depth_cm = 20
depth_ratio = 0.9
"""
WAIST_HEIGHT = 104.0


def f(x):
    return f"{x:.4f}".rstrip("0").rstrip(".")


def pt(x, y):
    return f"[{f(x)}, {f(y)}]"


def sector_piece(name, r_in, r_out, half_turn_deg, grain, place):
    """An annular sector about (0, 0) centred on the -y axis: hem arc, right side, waist arc,
    left side (counter-clockwise)."""
    a0 = math.radians(-90 - half_turn_deg)
    a1 = math.radians(-90 + half_turn_deg)
    P = lambda r, a: (r * math.cos(a), r * math.sin(a))
    hem0, hem1 = P(r_out, a0), P(r_out, a1)
    w1, w0 = P(r_in, a1), P(r_in, a0)
    return f"""
[[piece]]
name = "{name}"
grain_deg = {f(grain)}
start_cm = {pt(*hem0)}
[[piece.segment]]
name = "hem"
to_cm = {pt(*hem1)}
centre_cm = [0, 0]
turn = "ccw"
role = "hem"
[[piece.segment]]
name = "right"
to_cm = {pt(*w1)}
[[piece.segment]]
name = "waist"
to_cm = {pt(*w0)}
centre_cm = [0, 0]
turn = "cw"
role = "waist"
[[piece.segment]]
name = "left"
to_cm = {pt(*hem0)}
[piece.place]
{place}
"""


def seams(names):
    out = ""
    for k, n in enumerate(names):
        m = names[(k + 1) % len(names)]
        out += f"""
[[seam]]
a = "{n}.right"
b = "{m}.left"
direction = "reversed"
"""
    return out


def header(name, comment):
    return f"""# {comment}
# Written by make_examples.py; docs/GARMENT-FORMAT.md describes every key.
name = "{name}"
fabric = "silk"
spacing_cm = 2

{BODY}"""


def circular():
    r_w, length = 12.0, 45.0
    text = header("circular skirt", "A full circular skirt from two half circles (front, back), 45 cm long, waist 75.4 cm.")
    names = ["front", "back"]
    for name, az in zip(names, [-90, 90]):
        place = f'wrap = "cone"\norigin_cm = [0, 0]\nhalf_angle_deg = 90\nheight_cm = {f(WAIST_HEIGHT)}\nazimuth_deg = {az}'
        text += sector_piece(name, r_w, r_w + length, 90, 0, place)
    return text + seams(names)


def gored(grain):
    alpha = math.radians(20)
    r_w, length = 12.0, 55.0
    rho_w = r_w / math.sin(alpha)
    half = math.degrees(2 * math.pi * math.sin(alpha) / 4) / 2
    apex = WAIST_HEIGHT + rho_w * math.cos(alpha)
    kind = "bias" if grain else "straight grain"
    text = header(f"four-gore A-line skirt, {kind}",
                  f"A four-gore A-line skirt (flared 20 degrees from the waist), 55 cm long, each gore cut on the {kind} "
                  f"(grain_deg = {grain}).")
    names = ["front", "side_a", "back", "side_b"]
    for name, az in zip(names, [-90, 0, 90, 180]):
        place = (f'wrap = "cone"\norigin_cm = [0, 0]\nhalf_angle_deg = 20\nheight_cm = {f(apex)}\nazimuth_deg = {az}')
        text += sector_piece(name, rho_w, rho_w + length, half, grain, place)
    return text + seams(names)


def tube():
    radius, length = 17.0, 55.0
    half_w = math.pi * radius / 2
    text = header("straight tube skirt",
                  "A straight tube skirt from two rectangles (front, back), 55 cm long, 106.8 cm around, hanging from its "
                  "waistband held at 17 cm from the body's axis (no darts).")
    names = ["front", "back"]
    for name, az in zip(names, [-90, 90]):
        text += f"""
[[piece]]
name = "{name}"
grain_deg = 0
start_cm = {pt(-half_w, -length)}
[[piece.segment]]
name = "hem"
to_cm = {pt(half_w, -length)}
role = "hem"
[[piece.segment]]
name = "right"
to_cm = {pt(half_w, 0)}
[[piece.segment]]
name = "waist"
to_cm = {pt(-half_w, 0)}
role = "waist"
[[piece.segment]]
name = "left"
to_cm = {pt(-half_w, -length)}
[piece.place]
wrap = "cylinder"
origin_cm = [0, 0]
radius_cm = {f(radius)}
height_cm = {f(WAIST_HEIGHT)}
azimuth_deg = {az}
"""
    # front.right (up) meets back.left (down): reversed; back.right meets front.left.
    return text + seams(names)


if __name__ == "__main__":
    (HERE / "circular-skirt.toml").write_text(circular())
    (HERE / "gored-skirt-straight.toml").write_text(gored(0))
    (HERE / "gored-skirt-bias.toml").write_text(gored(45))
    (HERE / "tube-skirt.toml").write_text(tube())
