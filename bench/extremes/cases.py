"""The extremes matrix (issue 11): small scenes that push one parameter at a time to an
extreme, each built as the JSON that dipc's scene parser accepts (src/io/scene_parser.cpp).

Most cases vary one knob of a base scene: a 3×3×3 box (0.1 m) falling at 1 m/s under gravity
onto a 5×5×2 box (0.2 × 0.2 × 0.06 m) that rests just above a ground plane; 77 hexes. The
upper box is offset in x and y so that nothing is symmetric (a centred frictionless drop has no
unique outcome once it tips). Every case is small enough to run in seconds to a minute on one
core. Case names are file names; `group` says which knob a case varies (for the report).
"""
import math
import re

BASE_E, BASE_NU, RHO = 1e6, 0.4, 1000.0


def material(name, E, nu, rho, model='neo_hookean', **extra):
    """A materials[] entry; "model" is written only when it is not the default (neo_hookean)."""
    m = {'name': name, 'E': E, 'nu': nu, 'rho': rho, **extra}
    if model != 'neo_hookean':
        m['model'] = model
    return m


def box(name, size, resolution, origin, material='m', velocity=None, **extra):
    body = {'name': name, 'box': {'size': size, 'resolution': resolution, 'origin': origin},
            'material': material}
    if velocity is not None:
        body['initial_velocity'] = velocity
    body.update(extra)
    return body


def diagonal(bodies):
    """Bounding-box diagonal of the generated boxes at rest (what dhat_relative refers to)."""
    lo = [min(b['box']['origin'][d] for b in bodies) for d in range(3)]
    hi = [max(b['box']['origin'][d] + b['box']['size'][d] for b in bodies) for d in range(3)]
    return math.dist(lo, hi)


def scene(bodies, materials, dt, steps, dhat=1e-3, gravity=(0, 0, -9.81), planes=((0, 0, 0),),
          friction=0.0, dirichlet=None, contact=True):
    s = {'materials': materials,
         'geometry': bodies,
         'boundary_conditions': {'gravity': list(gravity)},
         'time': {'integrator': 'implicit_euler', 'dt': dt, 'steps': steps},
         'solver': {'mass': 'lumped'},
         'output': {'directory': 'output/extremes', 'name': 'run', 'every': 1}}
    if dirichlet:
        s['boundary_conditions']['dirichlet'] = dirichlet
    if contact:
        s['contact'] = {'enabled': True, 'dhat': dhat, 'dhat_relative': True, 'barrier_stiffness': 'adaptive',
                        'planes': [{'point': list(p), 'normal': [0, 0, 1]} for p in planes]}
        if friction:
            s['contact'].update({'friction': friction, 'epsv': 1e-3})
    return s


def drop(E=BASE_E, nu=BASE_NU, dt=0.01, steps=20, speed=1.0, gap=0.009, dhat=1e-3,
         rho_upper=RHO, rho_lower=RHO, volumetric='gauss_points', model='neo_hookean'):
    """The base scene: upper box falling onto the lower box on the ground plane."""
    materials = [material('upper', E, nu, rho_upper, model, volumetric=volumetric),
                 material('lower', E, nu, rho_lower, model, volumetric=volumetric)]
    bodies = [box('lower', [0.2, 0.2, 0.06], [5, 5, 2], [-0.1, -0.1, 0.001], 'lower'),
              box('upper', [0.1, 0.1, 0.1], [3, 3, 3], [-0.03, -0.04, 0.061 + gap], 'upper', [0, 0, -speed])]
    return scene(bodies, materials, dt, steps, dhat)


def impact(speed, model='neo_hookean'):
    """Box onto box in free space (no gravity, no plane): momentum is conserved exactly, and
    implicit Euler may only lose energy. dt 1e-3: at 200 m/s a step moves the box 2× its size,
    so only CCD stands between it and tunnelling."""
    materials = [material('m', BASE_E, BASE_NU, RHO, model)]
    bodies = [box('target', [0.2, 0.2, 0.06], [5, 5, 2], [-0.1, -0.1, 0.0]),
              box('bullet', [0.1, 0.1, 0.1], [3, 3, 3], [-0.03, -0.04, 0.07], velocity=[0, 0, -speed])]
    return scene(bodies, materials, 1e-3, 12, gravity=(0, 0, 0), planes=())


def thin_plate():
    """A plate one element thick with 100:1 elements (0.1 × 0.1 × 0.001 m), clamped on two
    sides, hit by a small box. d̂ 1e-4 (≈ 7e-5 m) stays below the plate's thickness."""
    materials = [{'name': 'plate', 'E': 1e8, 'nu': 0.3, 'rho': RHO}, {'name': 'm', 'E': BASE_E, 'nu': BASE_NU, 'rho': RHO}]
    bodies = [box('plate', [0.5, 0.5, 0.001], [5, 5, 1], [-0.25, -0.25, 0.0], 'plate'),
              box('block', [0.08, 0.08, 0.08], [2, 2, 2], [-0.02, -0.07, 0.005], 'm', [0, 0, -1])]
    dirichlet = [{'selection': 'plate.xmin', 'type': 'fixed'}, {'selection': 'plate.xmax', 'type': 'fixed'}]
    return scene(bodies, materials, 0.005, 20, dhat=1e-4, planes=(), dirichlet=dirichlet)


def stack(count=5):
    """count boxes stacked 2 mm apart on the ground, each shifted a little, friction 0.3."""
    materials = [{'name': 'm', 'E': BASE_E, 'nu': BASE_NU, 'rho': RHO}]
    bodies = []
    z = 0.001
    for k in range(count):
        size = 0.1 - 0.01 * k
        bodies.append(box(f'box{k}', [size, size, 0.04], [2, 2, 2], [-size / 2 + 0.004 * k, -size / 2 - 0.003 * k, z]))
        z += 0.04 + 0.002
    return scene(bodies, materials, 0.01, 30, friction=0.3)


def twisted_bar():
    """A 0.1 × 0.1 × 1 bar with its top turned by 4π about its axis (40 steps of 18°), bottom
    fixed, self-contact on: dipc applies each step's rotation in fractions if it would invert."""
    materials = [{'name': 'm', 'E': BASE_E, 'nu': 0.45, 'rho': 1100}]
    bodies = [box('bar', [0.1, 0.1, 1.0], [2, 2, 10], [-0.05, -0.05, 0.0])]
    steps, dt = 40, 0.025
    dirichlet = [{'selection': 'bar.zmin', 'type': 'fixed'},
                 {'selection': 'bar.zmax', 'type': 'rotation', 'axis': [0, 0, 1], 'center': [0, 0, 1],
                  'angular_velocity': 4 * math.pi / (steps * dt)}]
    return scene(bodies, materials, dt, steps, gravity=(0, 0, 0), planes=(), dirichlet=dirichlet)


def closer_than_dhat():
    """The upper box starts at half of d̂ above the lower one (already inside the barrier)."""
    bodies = drop()['geometry']
    dhat = 1e-3 * diagonal(bodies)
    return drop(gap=0.5 * dhat)


def squeeze_plates():
    """A soft box (E 1e5, ν 0.45, 0.1 m, 6³ hexes) between two steel kinematic plates closing at
    0.05 m/s each, μ 0.5, no gravity (issue 32): the plates travel 0.5 mm a step while the gap
    to them falls far below d̂."""
    materials = [material('m', 1e5, 0.45, RHO), material('steel', 2e11, 0.3, 7800.0)]
    plate = {'size': [0.3, 0.3, 0.02], 'resolution': [2, 2, 1]}
    bodies = [box('box', [0.1, 0.1, 0.1], [6, 6, 6], [-0.05, -0.05, -0.05]),
              box('bottom', plate['size'], plate['resolution'], [-0.15, -0.15, -0.0725], material='steel',
                  kinematic={'type': 'velocity', 'velocity': [0, 0, 0.05]}),
              box('top', plate['size'], plate['resolution'], [-0.15, -0.15, 0.0525], material='steel',
                  kinematic={'type': 'velocity', 'velocity': [0, 0, -0.05]})]
    return scene(bodies, materials, 0.01, 40, gravity=(0, 0, 0), planes=(), friction=0.5)


def tag(value):
    """1e+06 -> 1e6, 1e-05 -> 1e-5: case names that read like the values."""
    return re.sub(r'e([+-])0*(\d)', lambda m: 'e' + ('-' if m.group(1) == '-' else '') + m.group(2), f'{value:.0e}')


def all_cases():
    """{name: (group, scene)} in the order of the report."""
    cases = {}
    for E in (1e2, 1e4, 1e6, 1e8, 2e11):
        cases[f'E_{tag(E)}'] = ('Young modulus [Pa]', drop(E=E))
    for nu in (0.0, 0.3, 0.45, 0.49, 0.499, 0.4999):
        cases[f'nu_{nu:g}'] = ('Poisson ratio', drop(nu=nu))
    for nu in (0.499, 0.4999):  # the locking-free element (materials[].volumetric)
        cases[f'nu_{nu:g}_md'] = ('Poisson ratio, mean dilatation', drop(nu=nu, volumetric='mean_dilatation'))
    for nu in (0.3, 0.49, 0.4999):  # the second material (materials[].model)
        cases[f'nu_{nu:g}_snh'] = ('Poisson ratio, stable neo-Hookean', drop(nu=nu, model='stable_neo_hookean'))
    # The fall (gap) is scaled so that contact happens within the run at every dt.
    cases['dt_1e-5'] = ('time step [s]', drop(dt=1e-5, steps=40, speed=2.0, gap=4e-4))
    cases['dt_1e-3'] = ('time step [s]', drop(dt=1e-3, steps=30))
    cases['dt_1e-1'] = ('time step [s]', drop(dt=0.1, steps=10))
    for speed in (1, 20, 100, 200):
        cases[f'impact_{speed}'] = ('impact speed [m/s]', impact(speed))
    for speed in (20, 100):  # large compression on impact, stable neo-Hookean
        cases[f'impact_{speed}_snh'] = ('impact speed [m/s], stable neo-Hookean', impact(speed, 'stable_neo_hookean'))
    for dhat in (1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2):
        cases[f'dhat_{tag(dhat)}'] = ('d̂ / diagonal', drop(dhat=dhat))
    cases['heavy_on_light'] = ('density ratio 1e4', drop(rho_upper=RHO * 1e4))
    cases['light_on_heavy'] = ('density ratio 1e4', drop(rho_lower=RHO * 1e4))
    cases['thin_plate'] = ('geometry', thin_plate())
    cases['stack_5'] = ('geometry', stack(5))
    cases['twist_4pi'] = ('geometry', twisted_bar())
    cases['closer_than_dhat'] = ('initial state', closer_than_dhat())
    cases['squeeze_plates'] = ('kinematic plates', squeeze_plates())
    return cases


# Momentum is conserved only where no external force acts: no gravity, planes or Dirichlet
# conditions. Energy may only decrease (implicit Euler dissipates) where nothing does work on
# the bodies: no prescribed motion (Dirichlet conditions or kinematic bodies).
def prescribed_motion(s):
    return bool(s['boundary_conditions'].get('dirichlet')) or any('kinematic' in b for b in s['geometry'])


def conserves_momentum(s):
    return (not any(s['boundary_conditions'].get('gravity', [0, 0, 0])) and not prescribed_motion(s)
            and not s.get('contact', {}).get('planes'))


def energy_may_only_fall(s):
    return not prescribed_motion(s)
