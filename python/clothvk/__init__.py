"""clothvk: cloth simulation as Vulkan compute work, from Python.

    import clothvk
    with clothvk.Context() as ctx:
        scene = clothvk.Scene.load("assets/scenes/hanging.json",
                                   overrides={"render.size": [640, 360]})
        sim = clothvk.Simulation(ctx, scene)
        sim.step(60)
        xyz = sim.positions()            # numpy float32, shape (particles, 3), m
        print(sim.stats()["max_stretch"])
        renderer = clothvk.Renderer(sim, scene)
        image = renderer.draw()          # numpy uint8, shape (height, width, 4), sRGB
        renderer.write_png("frame.png")

A thin layer over libclothvk (cffi, ABI mode): every object owns one library object and
destroys it in close() (or at the end of a with block, or when collected); closing a
context closes its simulations, and closing a simulation closes its renderers, in the order
the library needs. Failures raise clothvk.Error with the library's sentence; a scene's are
also FileNotFoundError, KeyError or ValueError (SceneNotFoundError, ScenePathError,
SceneValueError), and bad arguments raise TypeError or ValueError before the library is called.
"""

import errno as _errno
import json
import os
import re
import time

import numpy as np

from ._ffi import ffi, lib

__all__ = ["Error", "SceneNotFoundError", "ScenePathError", "SceneValueError", "Context",
           "Scene", "Simulation", "Renderer"]

__version__ = ffi.string(lib.cvk_version()).decode()


def __dir__():
    # The public names only: the modules and the cffi objects this one uses stay reachable
    # (clothvk.lib, clothvk.ffi) but do not crowd dir(clothvk) or tab completion.
    return sorted(__all__ + ["__version__"])


class Error(RuntimeError):
    """A failed library call: message is the library's sentence, result the name of its
    cvk_result ("CVK_ERROR_INVALID_ARGUMENT"), code its number. The scene errors below are
    subclasses that are also the built-in exception a Python caller would catch."""

    def __init__(self, message, result=None, code=None):
        super().__init__(message)
        self.message = message
        self.result = result
        self.code = code

    def __str__(self):  # KeyError would quote it, OSError would prefix "[Errno 2]"
        return self.message


class SceneNotFoundError(Error, FileNotFoundError):
    """Scene.load's file does not exist (errno ENOENT, filename the path given)."""


class ScenePathError(Error, KeyError):
    """A key path the scene format does not have: an unknown key, or an index past the end of
    an array. key_path is the path as Python indexes the scene's JSON: ("cloths", 0, "mass")."""


class SceneValueError(Error, ValueError):
    """A scene that is not valid JSON, a value of the wrong kind or out of range, or an override
    that is not key=value. key_path as for ScenePathError, or None where no key is at fault."""


def _check(code, err):
    if code != lib.CVK_SUCCESS:
        name = ffi.string(lib.cvk_result_name(code)).decode()
        raise Error(ffi.string(err.message).decode(errors="replace"), name, int(code))


def _whole(value, what, maximum=None):
    """A count or index given from Python: a whole number, at least 0 (and at most maximum),
    said in Python's words rather than as cffi's OverflowError."""
    if isinstance(value, bool) or not hasattr(value, "__index__"):
        raise TypeError(f"{what} must be a whole number, got {type(value).__name__} {value!r}")
    value = value.__index__()
    if value < 0:
        raise ValueError(f"{what} must be at least 0, got {value}")
    if maximum is not None and value > maximum:
        raise ValueError(f"{what} must be at most {maximum}, got {value}")
    return value


def _text(pointer):
    return ffi.string(pointer).decode(errors="replace") if pointer != ffi.NULL else None


class _Handle:
    """One library object and how to destroy it, with the handles that must go before it
    (a context's simulations, a simulation's renderers). Plain data without __del__: when the
    garbage collector finalizes a cycle, its weak references are already cleared and the
    wrappers' finalizers run in any order, so the order lives here instead — releasing a
    handle releases its children first, and a handle already released (ptr None) does nothing.
    Nothing here reads module globals, which the interpreter's exit may already have cleared."""

    __slots__ = ("ptr", "destroy", "parent", "children")

    def __init__(self, ptr, destroy, parent=None):
        self.ptr = ptr
        self.destroy = destroy
        self.parent = parent
        self.children = []
        if parent is not None:
            parent.children.append(self)

    def release(self):
        while self.children:
            self.children[-1].release()
        if self.ptr is not None:
            ptr, self.ptr = self.ptr, None
            self.destroy(ptr)
        if self.parent is not None:
            self.parent.children.remove(self)
            self.parent = None


class _Owner:
    """A wrapper that owns one _Handle; close() (or the end of a with block, or collection)
    releases it."""

    _h = None

    def _live(self):
        if self._h is None or self._h.ptr is None:
            raise ValueError(f"{type(self).__name__} is closed")
        return self._h.ptr

    @property
    def closed(self):
        return self._h is None or self._h.ptr is None

    def close(self):
        if self._h is not None:
            self._h.release()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:  # interpreter shutdown: module globals may already be gone
            pass


class Context(_Owner):
    """The Vulkan instance, device and queue. validation: None = on when
    $CLOTHVK_VALIDATION is "1" (as in C), True = on, False = off. device: an index or a
    substring of the device name; None = $CLOTHVK_DEVICE, else the first device.
    Validation messages are collected in .messages."""

    def __init__(self, validation=None, device=None):
        self.messages = []
        messages = self.messages  # the callback must not keep the context alive

        @ffi.callback("void(void*, const char*)")
        def log(user, message):
            messages.append(ffi.string(message).decode(errors="replace"))

        self._device = ffi.new("char[]", str(device).encode()) if device is not None else None
        desc = ffi.new("cvk_context_desc*", lib.cvk_default_context_desc())
        desc.validation = {None: 0, True: 1, False: -1}[validation]
        desc.device_name = self._device if self._device is not None else ffi.NULL
        desc.log = log
        out = ffi.new("cvk_context**")
        err = ffi.new("cvk_error*")
        _check(lib.cvk_context_create(desc, out, err), err)

        # The callback must outlive the context: destroying its children can still log.
        def destroy(context, callback=log, destroy_context=lib.cvk_context_destroy):
            destroy_context(context)

        self._h = _Handle(out[0], destroy)

    def info(self):
        i = lib.cvk_context_get_info(self._live())
        return {
            "device_name": _text(i.device_name), "api_version": i.api_version,
            "adopted": bool(i.adopted), "validation": bool(i.validation),
            "timestamps": bool(i.timestamps), "subgroup_size": i.subgroup_size,
            "max_particles": i.max_particles, "graphics": bool(i.graphics),
            "max_image_size": i.max_image_size,
            "device_bytes": i.device_bytes,
            "device_peak_bytes": i.device_peak_bytes,
        }

    def validation_message_count(self):
        return lib.cvk_context_validation_message_count(self._live())


def _override_strings(overrides):
    """{"solver.linear": "jacobi", "render.size": [64, 48]} or ["key=value", ...] ->
    "key=value" strings; a value that is not a string is written as JSON."""
    if overrides is None:
        return []
    if isinstance(overrides, dict):
        for key in overrides:
            if not isinstance(key, str):
                raise TypeError(f"overrides: a key must be a dotted key path string such as "
                                f"\"solver.omega\", got {type(key).__name__} {key!r}")
            if not key:
                raise ValueError("overrides: a key must not be empty")
            if "=" in key:
                raise ValueError(f"overrides: the key {key!r} holds '='; the value goes in the "
                                 "dict's value")
        return [f"{k}={v if isinstance(v, str) else json.dumps(v)}" for k, v in overrides.items()]
    if isinstance(overrides, (str, bytes)):
        raise TypeError("overrides must be a dict or a list of \"key=value\" strings, got a "
                        "single string")
    return [str(o) for o in overrides]


def _key_path(dotted):
    """"cloths.0.mass" -> ("cloths", 0, "mass"): the path as Python indexes the scene's JSON."""
    return tuple(int(part) if part.isdigit() else part for part in dotted.split("."))


# The library's scene messages: "source: key.path: problem", with " (from --set)" after a path an
# override wrote, and "source: --set key.path: problem" for an override that names no place.
_PATH_MESSAGE = re.compile(r"(?P<path>[\w.-]+)(?P<set> \(from --set\))?: (?P<problem>.*)", re.S)
_SET_VALUE_PROBLEMS = ("expected key.path=value", "the value is neither JSON nor UTF-8 text")


def _scene_error(message, result, code, source, overrides):
    """The exception for a scene that failed to load: ScenePathError (a KeyError) for a key path
    the format does not have, SceneValueError (a ValueError) for the rest, each with key_path;
    the library's "--set" wording becomes the overrides argument's."""
    prefix = f"{source}: "
    if not message.startswith(prefix):  # "source:line:column: malformed JSON"
        return _with_path(SceneValueError(message, result, code), None)
    rest = message[len(prefix):]
    if rest.startswith("--set "):
        entry = rest[len("--set "):]
        # What the library names (a key path, or a whole entry without "="), and how the
        # caller wrote it: a dict key, or an entry of the list.
        if isinstance(overrides, dict):
            names = {key: f"overrides[{key!r}]" for key in overrides}
        else:
            names = {}
            for text in _override_strings(overrides):
                names.setdefault(text.split("=", 1)[0], f"overrides entry {text!r}")
                names.setdefault(text, f"overrides entry {text!r}")
        for given in sorted(names, key=len, reverse=True):
            if entry.startswith(given + ": "):
                problem = entry[len(given) + 2:]
                name = names[given]
                text = f"{prefix}{name}: {problem}"
                if problem.startswith(_SET_VALUE_PROBLEMS) or "holds a number too large" in problem:
                    return _with_path(SceneValueError(text, result, code), None)
                return _with_path(ScenePathError(text, result, code), _key_path(given))
        return _with_path(SceneValueError(message, result, code), None)
    match = _PATH_MESSAGE.fullmatch(rest)
    if not match:  # "the top level must be an object"
        return _with_path(SceneValueError(message, result, code), None)
    origin = " (from overrides)" if match["set"] else ""
    text = f"{prefix}{match['path']}{origin}: {match['problem']}"
    kind = ScenePathError if match["problem"].startswith("unknown key") else SceneValueError
    return _with_path(kind(text, result, code), _key_path(match["path"]))


def _with_path(error, key_path):
    error.key_path = key_path
    return error


class Scene(_Owner):
    """A scene read from JSON (the format in docs/scene-format.md); it owns its description."""

    def __init__(self, ptr):
        self._h = _Handle(ptr, lib.cvk_scene_destroy)

    @classmethod
    def _make(cls, call, source, overrides, path=None):
        strings = [ffi.new("char[]", s.encode()) for s in _override_strings(overrides)]
        array = ffi.new("const char*[]", strings) if strings else ffi.NULL
        out = ffi.new("cvk_scene**")
        err = ffi.new("cvk_error*")
        code = call(array, len(strings), out, err)
        if code == lib.CVK_SUCCESS:
            return cls(out[0])
        message = ffi.string(err.message).decode(errors="replace")
        result = ffi.string(lib.cvk_result_name(code)).decode()
        if code == lib.CVK_ERROR_IO and path is not None and not os.path.lexists(path):
            error = SceneNotFoundError(message, result, int(code))
            error.errno, error.strerror, error.filename = \
                _errno.ENOENT, os.strerror(_errno.ENOENT), path
            raise error
        if code in (lib.CVK_ERROR_INVALID_ARGUMENT, lib.CVK_ERROR_PARSE):
            raise _scene_error(message, result, int(code), source, overrides)
        raise Error(message, result, int(code))

    @classmethod
    def load(cls, path, overrides=None):
        """Reads a scene file; overrides replace keys by dotted path before validation."""
        path = os.fspath(path)
        p = ffi.new("char[]", os.fsencode(path))
        return cls._make(lambda a, n, out, err: lib.cvk_scene_load(p, a, n, out, err),
                         path, overrides, path=path)

    @classmethod
    def parse(cls, text, source_name="scene", overrides=None):
        """The same from JSON text; source_name stands in for the file name in messages."""
        t = ffi.new("char[]", text.encode())
        s = ffi.new("char[]", source_name.encode())
        return cls._make(lambda a, n, out, err: lib.cvk_scene_parse(t, s, a, n, out, err),
                         source_name, overrides)

    @property
    def _desc(self):
        return lib.cvk_scene_get_desc(self._live())

    @property
    def name(self):
        return _text(self._desc.name)

    @property
    def frames(self):
        """The scene's default frame count for the tools."""
        return self._desc.frames

    @property
    def dt(self):
        return self._desc.dt

    @property
    def substeps(self):
        return self._desc.substeps

    @property
    def cloth_count(self):
        return self._desc.cloth_count

    @property
    def render_size(self):
        return tuple(self._desc.render.size)


def _float3(array, count, what):
    """A C-contiguous float32 (count, 3) array: the one given when it already is one."""
    a = np.ascontiguousarray(array, dtype=np.float32)
    if a.shape != (count, 3):
        raise ValueError(f"{what}: expected shape ({count}, 3), got {a.shape}")
    return a


def _out_float3(out, count, what):
    if out is None:
        return np.empty((count, 3), dtype=np.float32)
    if (out.dtype != np.float32 or out.shape != (count, 3) or not out.flags.c_contiguous
            or not out.flags.writeable):
        raise ValueError(f"{what}: expected a writable C-contiguous float32 array of shape "
                         f"({count}, 3), got {out.dtype} {out.shape}")
    return out


def _ptr(cdecl, array):
    return ffi.from_buffer(cdecl, array) if array is not None else ffi.NULL


# Simulation.step's chunks: it doubles a chunk of frames while one takes under half of this
# long, up to _MAX_CHUNK frames. 2**31 frames in one cvk_sim_step on lavapipe held 3.4 GB of
# queued submissions after 30 s and did not answer Ctrl-C.
_CHUNK_SECONDS = 0.1
_U32_MAX = 2**32 - 1
_MAX_CHUNK = 4096


class Simulation(_Owner):
    """A simulation of a scene on a context (the scene is copied; it may be closed after)."""

    def __init__(self, context, scene, workgroup_size=0, max_workgroups=0, timing=True,
                 grab=False, search_lanes=0, fused_shared_memory=None):
        self.context = context
        desc = ffi.new("cvk_sim_desc*", lib.cvk_default_sim_desc())
        desc.scene = scene._desc
        desc.workgroup_size = _whole(workgroup_size, "workgroup_size", _U32_MAX)
        desc.max_workgroups = _whole(max_workgroups, "max_workgroups", _U32_MAX)
        desc.timing = 0 if timing else -1
        desc.grab = grab
        desc.search_lanes = _whole(search_lanes, "search_lanes", _U32_MAX)
        if fused_shared_memory is not None and not isinstance(fused_shared_memory, bool):
            raise TypeError("fused_shared_memory must be None (the library's choice), True or "
                            f"False, got {fused_shared_memory!r}")
        desc.fused_shared_memory = {None: 0, True: 1, False: -1}[fused_shared_memory]
        out = ffi.new("cvk_sim**")
        err = ffi.new("cvk_error*")
        _check(lib.cvk_sim_create(context._live(), desc, out, err), err)
        self._h = _Handle(out[0], lib.cvk_sim_destroy, parent=context._h)

    def step(self, frames=1):
        """Advances `frames` frames (any whole number) and waits until they are done. The frames
        go to the library in chunks of about a tenth of a second each, waited for one by one:
        memory stays bounded for any count (the driver holds every submission until it ran),
        and Ctrl-C raises KeyboardInterrupt between chunks, with the frames done so far kept
        (stats()["frames"] counts them). Chunks change no bit of the result."""
        frames = _whole(frames, "frames")
        sim = self._live()
        err = ffi.new("cvk_error*")
        chunk = 1
        while frames > 0:
            count = min(frames, chunk)
            start = time.monotonic()
            _check(lib.cvk_sim_step(sim, count, err), err)
            frames -= count
            if time.monotonic() - start < _CHUNK_SECONDS / 2 and chunk < _MAX_CHUNK:
                chunk *= 2

    @property
    def particle_count(self):
        return lib.cvk_sim_particle_count(self._live())

    @property
    def triangle_count(self):
        return lib.cvk_sim_triangle_count(self._live())

    def positions(self, out=None):
        """Positions (m), float32 (particles, 3), cloth by cloth, read straight into the
        array (out, when given, is filled and returned)."""
        n = self.particle_count
        xyz = _out_float3(out, n, "positions")
        err = ffi.new("cvk_error*")
        _check(lib.cvk_sim_read_positions(self._live(), _ptr("float[]", xyz), n, err), err)
        return xyz

    def state(self):
        """(positions (m), velocities (m/s)), each float32 (particles, 3)."""
        n = self.particle_count
        xyz = np.empty((n, 3), dtype=np.float32)
        vel = np.empty((n, 3), dtype=np.float32)
        err = ffi.new("cvk_error*")
        _check(lib.cvk_sim_read_state(self._live(), _ptr("float[]", xyz), _ptr("float[]", vel),
                                      n, err), err)
        return xyz, vel

    def write_state(self, positions, velocities=None):
        """Replaces positions and velocities (None: at rest)."""
        n = self.particle_count
        xyz = _float3(positions, n, "positions")
        vel = _float3(velocities, n, "velocities") if velocities is not None else None
        err = ffi.new("cvk_error*")
        _check(lib.cvk_sim_write_state(self._live(), _ptr("float[]", xyz), _ptr("float[]", vel),
                                       n, err), err)

    def write_positions(self, positions):
        """Replaces positions and sets every velocity to zero."""
        n = self.particle_count
        xyz = _float3(positions, n, "positions")
        err = ffi.new("cvk_error*")
        _check(lib.cvk_sim_write_positions(self._live(), _ptr("float[]", xyz), n, err), err)

    def mesh(self):
        """(positions (particles, 3) float32, unit normals (particles, 3) float32, triangles
        (triangles, 3) uint32 particle indices; a torn triangle has three equal indices)."""
        n, t = self.particle_count, self.triangle_count
        xyz = np.empty((n, 3), dtype=np.float32)
        normals = np.empty((n, 3), dtype=np.float32)
        triangles = np.empty((t, 3), dtype=np.uint32)
        err = ffi.new("cvk_error*")
        _check(lib.cvk_sim_read_mesh(self._live(), _ptr("float[]", xyz),
                                     _ptr("float[]", normals), _ptr("uint32_t[]", triangles),
                                     n, t, err), err)
        return xyz, normals, triangles

    def pick(self, origin, direction, radius):
        """The particle nearest the ray's origin among those it passes within `radius` (m) of,
        in front of the origin, found on the device: a dict (cloth, index within the cloth,
        distance along the ray in m, position in m), or None when the ray hits none."""
        out = ffi.new("cvk_pick_result*")
        err = ffi.new("cvk_error*")
        _check(lib.cvk_sim_pick(self._live(), [float(v) for v in origin],
                                [float(v) for v in direction], float(radius), out, err), err)
        if not out.hit:
            return None
        return {"cloth": out.particle.cloth, "index": out.particle.index,
                "distance": out.distance, "position": list(out.position)}

    def grab(self, cloth, index, target, radius=0.0):
        """Drags particle `index` of cloth `cloth` to `target` (m) over the next frame and holds
        it there (see cvk_sim_grab: one grab at a time; call again to move the target). With a
        radius (m), the free particles of the cloth within it are held too, at their offsets
        (cvk_sim_grab_within)."""
        err = ffi.new("cvk_error*")
        particle = ffi.new("cvk_particle*", {"cloth": _whole(cloth, "cloth", _U32_MAX),
                                             "index": _whole(index, "index", _U32_MAX)})
        target = [float(v) for v in target]
        if radius:
            _check(lib.cvk_sim_grab_within(self._live(), particle[0], float(radius), target, err),
                   err)
        else:
            _check(lib.cvk_sim_grab(self._live(), particle[0], target, err), err)

    def release(self):
        """Lets the grabbed particle go, with the velocity of its last substep."""
        lib.cvk_sim_release(self._live())

    def cloths(self):
        """One dict per cloth, in scene order: name, particle and triangle ranges, mesh."""
        sim = self._live()
        result = []
        for c in range(lib.cvk_sim_cloth_count(sim)):
            i = lib.cvk_sim_get_cloth(sim, c)
            result.append({
                "name": _text(i.name), "first_particle": i.first_particle,
                "particle_count": i.particle_count, "first_triangle": i.first_triangle,
                "triangle_count": i.triangle_count, "mesh": bool(i.mesh),
            })
        return result

    @property
    def notes(self):
        """The notes on the scene: one sentence for each key it sets that has no effect."""
        sim = self._live()
        return [_text(lib.cvk_sim_note(sim, i)) for i in range(lib.cvk_sim_note_count(sim))]

    def stats(self):
        """The fields of cvk_sim_stats as a dict (passes: a list of dicts)."""
        st = ffi.new("cvk_sim_stats*")
        err = ffi.new("cvk_error*")
        _check(lib.cvk_sim_get_stats(self._live(), st, err), err)
        result = {}
        for name, _ in ffi.typeof("cvk_sim_stats").fields:
            if name == "passes":
                continue
            value = getattr(st, name)
            result[name] = list(value) if isinstance(value, ffi.CData) else value
        result["passes"] = [
            {"name": _text(p.name), "gpu_ms": p.gpu_ms, "dispatches": p.dispatches}
            for p in st.passes[0:min(st.pass_count, len(st.passes))]
        ]
        return result

    def plan(self):
        """The step plan (passes, dispatches, workgroups) as text."""
        sim = self._live()
        capacity = 4096
        while True:
            text = ffi.new("char[]", capacity)
            needed = lib.cvk_sim_describe_plan(sim, text, capacity)
            if needed < capacity:
                return ffi.string(text).decode(errors="replace")
            capacity = needed + 1


class Renderer(_Owner):
    """Offscreen images of a simulation, as the scene's "render" block says (scene None:
    the library's defaults). Creating it draws the first frame."""

    def __init__(self, sim, scene=None):
        self.sim = sim
        if scene is not None:
            desc = ffi.addressof(scene._desc.render)
        else:
            desc = ffi.new("cvk_render_desc*", lib.cvk_default_render_desc())
        err = ffi.new("cvk_error*")
        mesh = ffi.new("cvk_mesh**")
        _check(lib.cvk_mesh_create(sim._live(), ffi.NULL, mesh, err), err)
        mesh = mesh[0]
        out = ffi.new("cvk_renderer**")
        code = lib.cvk_renderer_create(mesh, desc, out, err)
        if code != lib.CVK_SUCCESS:
            lib.cvk_mesh_destroy(mesh)
            _check(code, err)

        # The renderer, then the mesh it draws (the functions bound now: at interpreter
        # shutdown the module's globals may be gone before this runs).
        def destroy(renderer, mesh=mesh, destroy_renderer=lib.cvk_renderer_destroy,
                    destroy_mesh=lib.cvk_mesh_destroy):
            destroy_renderer(renderer)
            destroy_mesh(mesh)

        self._h = _Handle(out[0], destroy, parent=sim._h)

    def draw(self):
        """Draws the current particles; returns the image, uint8 (height, width, 4) RGBA,
        sRGB, rows top to bottom (a copy: the library's buffer is reused by the next draw)."""
        err = ffi.new("cvk_error*")
        _check(lib.cvk_renderer_draw(self._live(), err), err)
        return self.image()

    def image(self):
        """A copy of the last frame drawn, as draw() returns it."""
        im = lib.cvk_renderer_get_image(self._live())
        rows = np.frombuffer(ffi.buffer(im.pixels, im.row_bytes * im.height), dtype=np.uint8)
        rows = rows.reshape(im.height, im.row_bytes)
        return rows[:, :4 * im.width].reshape(im.height, im.width, 4).copy()

    def write_png(self, path):
        """Writes the last frame drawn as a PNG (complete or absent: written, then renamed)."""
        im = ffi.new("cvk_image*", lib.cvk_renderer_get_image(self._live()))
        err = ffi.new("cvk_error*")
        _check(lib.cvk_image_write_png(im, str(path).encode(), err), err)
