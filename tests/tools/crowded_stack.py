"""The crowded stack that lavapipe's loop limit cuts detection short on (docs/limits.md,
lavapipe's loop budget): 500 cloths of 4 x 4 stacked 0.04 mm apart, so every triangle lies in
one cell of the detection's hash. Shared by tests/tools/test_loop_budget.py (the tool) and
python/tests/test_loop_budget.py (the library through Python). Plain standard library."""

LAYERS = 500
SPACING = 0.00004  # m between layers
THICKNESS = 0.00002
PARTICLES_PER_LAYER = 16  # a 4 x 4 grid


def scene():
    """The stack as a scene file's JSON object."""
    cloths = [{"name": f"layer{i}", "grid": [4, 4], "size": [0.2, 0.2],
               "origin": [-0.1, 0.3 + i * SPACING, -0.1], "u_axis": [1, 0, 0],
               "v_axis": [0, 0, 1], "mass": 0.05} for i in range(LAYERS)]
    return {"name": "crowded-stack", "dt": 0.002, "substeps": 1, "frames": 1,
            "gravity": [0, 0, 0],
            "solver": {"linear": "rbgs", "outer_iterations": 1, "inner_iterations": 1},
            "collision": {"self": True, "thickness": THICKNESS}, "cloths": cloths}
