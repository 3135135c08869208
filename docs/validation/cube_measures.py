#!/usr/bin/env python3
# Cube drape measures from drape.obj + report.json: energy terms, lowest point, hanging depth
# per side (cube top z = 0.5 m minus the lowest particle in the side's middle band
# |other coordinate| < 0.25 m beyond the cube face), half-width of the bounding box.
import json, sys
d = sys.argv[1]
v = [tuple(map(float, l.split()[1:4])) for l in open(d + '/drape.obj') if l.startswith('v ')]
r = json.load(open(d + '/report.json'))
top = 0.5
def band(sel):
    zs = [p[2] for p in v if sel(p)]
    return top - min(zs) if zs else float('nan')
sides = {'+x': band(lambda p: p[0] > 0.25 and abs(p[1]) < 0.25), '-x': band(lambda p: p[0] < -0.25 and abs(p[1]) < 0.25),
         '+y': band(lambda p: p[1] > 0.25 and abs(p[0]) < 0.25), '-y': band(lambda p: p[1] < -0.25 and abs(p[0]) < 0.25)}
e = r['energy']
hw = max(max(abs(p[0]) for p in v), max(abs(p[1]) for p in v))
print(json.dumps({'grid': r.get('grid'), 'energy': e, 'lowest_z_m': min(p[2] for p in v), 'hang_m': sides, 'half_width_m': hw,
                  'steps': r.get('steps'), 'iterations': r.get('iterations'), 'wall_time_s': r.get('wall_time_s'), 'converged': r.get('converged')}))
