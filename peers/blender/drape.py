"""Blender peer of clothvk's contact drape (assets/scenes/contact-drape.json).

Run (one thread is the standard way; everything after "--" is this script's):

    blender -b -noaudio -t 1 --factory-startup --python peers/blender/drape.py -- \
        [--grid N] [--frames F] [--no-self] [--csv FILE] [--quality Q] [--dist-frac D] [--per-frame]

The scene, built from nothing: a 1.2 m square cloth of N x N vertices (default 40) and 0.144 kg in
all for every N (so only the resolution changes), horizontal at 0.8 m over a sphere of radius 0.3 m
centred at 0.3 m, a ground plane at 0, gravity 9.81, 60 frames at 60 frames per second, Coulomb
friction 0.3, self-collision on unless --no-self. clothvk is y-up and Blender z-up: clothvk
(x, y, z) is Blender (x, -z, y).

Units. Blender's cloth solver multiplies gravity by 0.001, i.e. it works in a time unit of
tau = sqrt(0.001) s (about 1/31.6 s) per frame whatever the scene's frame rate; forces are in
kg m / tau^2 = 1e-3 N. So:
  - time_scale = 1 / (fps * tau) makes one frame 1/60 s (free fall checked: 1.23 m in 30 frames);
  - tension/compression/shear: Blender's spring constant is stiffness / spacing, so clothvk's
    1e6 N/m springs are stiffness = 1e6 * 1e-3 * spacing (about 31 at N = 40);
  - bending (angular model): bending_stiffness = 1e-6, modest, chosen so the cloth drapes. By our
    reading of Blender's angular spring (k = bending * rest length * 0.1 per hinge) that is a
    bending rigidity of roughly 1e-4 N m, a bending length (B / (rho g))^(1/3) of a few cm on
    this 0.1 kg/m^2 cloth; clothvk's 2e4 N/m bend springs have no exact counterpart;
  - air damping: drag = 0.01 * air_damping * v, set to decay velocity at 0.96 / s like clothvk's
    damping 0.002 per 1/480 s substep; spring and bending damping 0;
  - friction: Blender's collision response takes cloth_friction * 0.01 (and self_friction *
    0.01) as the Coulomb coefficient, so 30 is 0.3.
Collision distances: object collision distance and self-collision distance 0.25 x the vertex
spacing (--dist-frac; Blender's floor is 0.001 m), colliders' outer thickness 0.001 m (the
minimum), collision quality 2 (Blender's default). clothvk's default thickness is 0.5 x spacing.

Steps: quality 5 (5 implicit steps of 1/300 s a frame; clothvk's scene takes 8 substeps of
1/480 s). Blender's object collisions are not continuous: at grid 80 the cloth, arriving at about
2 m/s, goes through the sphere at quality 5 (and 8, 10) and drapes at quality 15; at grid 160
it goes through at 15 and drapes at 30. The check after the last frame says drape_ok=no when a
vertex is inside the sphere (by more than 2 mm, the UV sphere being faceted) or below the
ground, or an edge is stretched by 10 % or more.

Timing: frame_set(f) for f = 1..F, each timed with time.perf_counter(). Frame 1 is the rest pose
(Blender caches it, nothing is simulated), so ms_per_frame_mean/median are over the F - 1
simulated frames 2..F; total_s is the sum over all F calls. The printed line and the CSV row
(--csv, header if new) end with the quality and drape_ok.
"""
import argparse
import csv
import math
import os
import statistics
import sys
import time

import bpy

SIZE = 1.2          # m, side of the cloth
MASS = 0.144        # kg, whole cloth, every N
HEIGHT = 0.8        # m
SPHERE_R = 0.3      # m
SPHERE_Z = 0.3      # m
FPS = 60
GRAVITY = 9.81
FRICTION = 0.3
K_SPRING = 1.0e6    # N/m, clothvk's structural and shear springs
BEND_RIGIDITY = 1.0e-4  # N m
DAMP_RATE = 0.002 * 480  # 1/s, clothvk's damping 0.002 per 1/480 s substep
QUALITY = 5         # Blender cloth steps per frame
TAU = math.sqrt(0.001)  # s, Blender cloth's time unit (gravity * 0.001)


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="drape.py", description=__doc__.split("\n")[0])
    p.add_argument("--grid", type=int, default=40, help="vertices per side (default 40)")
    p.add_argument("--frames", type=int, default=60, help="frames (default 60)")
    p.add_argument("--no-self", action="store_true", help="self-collision off")
    p.add_argument("--csv", help="append a row to this CSV (header if new)")
    p.add_argument("--dist-frac", type=float, default=0.25,
                   help="collision distances as a fraction of the spacing (default 0.25)")
    p.add_argument("--quality", type=int, default=QUALITY,
                   help=f"cloth steps per frame (default {QUALITY})")
    p.add_argument("--per-frame", action="store_true", help="print each frame's milliseconds")
    a = p.parse_args(argv)
    if a.grid < 2 or a.frames < 2 or a.quality < 1:
        p.error("--grid and --frames must be at least 2, --quality at least 1")
    return a


def blender_threads():
    """The -t/--threads value Blender was started with (0 or absent: all cores)."""
    args = sys.argv[:sys.argv.index("--")] if "--" in sys.argv else sys.argv
    for i, s in enumerate(args):
        if s in ("-t", "--threads") and i + 1 < len(args):
            return args[i + 1]
    return "auto"


def clear_scene():
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.materials, bpy.data.cameras, bpy.data.lights):
        for block in list(coll):
            coll.remove(block)


def add_collider(ob):
    ob.modifiers.new("Collision", "COLLISION")
    c = ob.collision
    c.use = True
    c.cloth_friction = FRICTION * 100.0   # Blender uses cloth_friction * 0.01 as Coulomb's mu
    c.thickness_outer = 0.001
    c.thickness_inner = 0.001
    c.use_culling = False


def build(grid, frames, use_self, dist_frac, quality):
    sc = bpy.context.scene
    sc.render.fps = FPS
    sc.render.fps_base = 1.0
    sc.frame_start = 1
    sc.frame_end = frames
    sc.use_gravity = True
    sc.gravity = (0.0, 0.0, -GRAVITY)
    sc.frame_set(1)

    spacing = SIZE / (grid - 1)
    m_v = MASS / (grid * grid)

    # Blender 3.4 counts the grid primitive's subdivisions in faces: N - 1 gives N x N vertices.
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=grid - 1, y_subdivisions=grid - 1, size=SIZE,
                                    location=(0.0, 0.0, HEIGHT))
    cloth = bpy.context.active_object
    cloth.name = "drape"
    nv = len(cloth.data.vertices)
    print(f"blender-drape vertex count {nv} (grid {grid}: expected {grid * grid})")
    if nv != grid * grid:
        raise SystemExit(f"drape.py: grid mesh has {nv} vertices, not {grid * grid}")

    mod = cloth.modifiers.new("Cloth", "CLOTH")
    s = mod.settings
    s.quality = quality
    s.time_scale = 1.0 / (FPS * TAU)
    s.mass = m_v
    s.air_damping = DAMP_RATE * m_v * TAU / 0.01
    s.bending_model = "ANGULAR"
    k = K_SPRING * 1e-3 * spacing
    s.tension_stiffness = k
    s.compression_stiffness = k
    s.shear_stiffness = k
    s.bending_stiffness = BEND_RIGIDITY / 100.0
    s.tension_damping = 0.0
    s.compression_damping = 0.0
    s.shear_damping = 0.0
    s.bending_damping = 0.0
    s.use_pressure = False
    s.use_internal_springs = False
    cs = mod.collision_settings
    dist = max(0.001, dist_frac * spacing)
    cs.use_collision = True
    cs.distance_min = dist
    cs.collision_quality = 2
    cs.use_self_collision = use_self
    cs.self_distance_min = dist
    cs.self_friction = FRICTION * 100.0
    mod.point_cache.frame_start = 1
    mod.point_cache.frame_end = frames

    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=SPHERE_R,
                                         location=(0.0, 0.0, SPHERE_Z))
    ball = bpy.context.active_object
    ball.name = "ball"
    add_collider(ball)

    bpy.ops.mesh.primitive_plane_add(size=4.0, location=(0.0, 0.0, 0.0))
    ground = bpy.context.active_object
    ground.name = "ground"
    add_collider(ground)

    print(f"blender-drape settings spacing={spacing:.5f} vertex_mass={m_v:.3e} "
          f"stiffness(tension=compression=shear)={k:.4g} bending={s.bending_stiffness:.3g} "
          f"air_damping={s.air_damping:.3g} time_scale={s.time_scale:.4f} quality={s.quality} "
          f"distance_min={cs.distance_min:.4f} self_distance_min={cs.self_distance_min:.4f}")
    return cloth


def check(cloth, grid):
    dg = bpy.context.evaluated_depsgraph_get()
    ev = cloth.evaluated_get(dg)
    mw = ev.matrix_world
    pts = [mw @ v.co for v in ev.data.vertices]
    zs = [p.z for p in pts]
    centre = (0.0, 0.0, SPHERE_Z)
    dmin = min(math.dist(tuple(p), centre) for p in pts)
    c = pts[(grid // 2) * grid + grid // 2]
    spacing = SIZE / (grid - 1)
    stretch = max((pts[e.vertices[0]] - pts[e.vertices[1]]).length for e in ev.data.edges) / spacing
    ok = dmin >= SPHERE_R - 0.002 and min(zs) >= -0.001 and stretch < 1.10
    print(f"blender-drape last frame: vertices={len(pts)} z_min={min(zs):.4f} z_max={max(zs):.4f} "
          f"centre_vertex_z={c.z:.4f} min_distance_to_sphere_centre={dmin:.4f} (radius {SPHERE_R}) "
          f"max_edge_stretch={100.0 * (stretch - 1.0):.2f}% drape_ok={'yes' if ok else 'no'}")
    return ok


def main():
    a = parse_args()
    use_self = not a.no_self
    clear_scene()
    cloth = build(a.grid, a.frames, use_self, a.dist_frac, a.quality)
    print("blender-drape load average at start: %.2f %.2f %.2f" % os.getloadavg())
    times = []
    for f in range(1, a.frames + 1):
        t0 = time.perf_counter()
        bpy.context.scene.frame_set(f)
        times.append(time.perf_counter() - t0)
    sim = [t * 1000.0 for t in times[1:]]
    if a.per_frame:
        print("blender-drape per-frame ms (frames 2..F): " + " ".join(f"{t:.0f}" for t in sim))
    mean, median, total = statistics.fmean(sim), statistics.median(sim), sum(times)
    ok = check(cloth, a.grid)
    line = (f"blender-drape grid={a.grid} self={'on' if use_self else 'off'} frames={a.frames} "
            f"ms_per_frame_mean={mean:.2f} ms_per_frame_median={median:.2f} total_s={total:.3f} "
            f"quality={a.quality} drape_ok={'yes' if ok else 'no'}")
    print(line, flush=True)
    if a.csv:
        new = not os.path.exists(a.csv) or os.path.getsize(a.csv) == 0
        with open(a.csv, "a", newline="") as fh:
            w = csv.writer(fh)
            if new:
                w.writerow(["grid", "self", "frames", "ms_per_frame_mean", "ms_per_frame_median",
                            "total_s", "blender_version", "threads", "quality", "drape_ok"])
            w.writerow([a.grid, "on" if use_self else "off", a.frames, f"{mean:.2f}",
                        f"{median:.2f}", f"{total:.3f}", bpy.app.version_string,
                        blender_threads(), a.quality, "yes" if ok else "no"])


main()
