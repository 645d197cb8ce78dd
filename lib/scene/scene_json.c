/* The scene format's tables: every block of a scene file (cloths, colliders, the solver, the
   camera, ...) as a table of its keys, with the readers of the values only this format has.
   scene_load.c reads a text with cvk_scene_table. Every message starts with the file name,
   then the key path (the same path --set takes), then the problem. */
#include "scene/scene_read.h"

#include "core/error.h"

#include <inttypes.h>
#include <math.h>
#include <stddef.h>

/* ---- the scene's tables ---- */

static const char* method_name(int v)
{
    return cvk_method_name((cvk_method)v);
}

static const char* linear_name(int v)
{
    return cvk_linear_solver_name((cvk_linear_solver)v);
}

static cvk_result read_method(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    int v = 0;
    cvk_result r = cvk_read_enum(rd, value, path, "method", method_name, &v);
    if (r == CVK_SUCCESS)
        *(cvk_method*)dest = (cvk_method)v;
    return r;
}

static const char* fuse_name(int v)
{
    return v >= 0 ? cvk_fuse_name((cvk_fuse)v) : NULL;
}

static cvk_result read_fuse(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path,
                            void* dest)
{
    (void)f;
    int v = 0;
    cvk_result r = cvk_read_enum(rd, value, path, "fuse mode", fuse_name, &v);
    if (r == CVK_SUCCESS)
        *(cvk_fuse*)dest = (cvk_fuse)v;
    return r;
}

static cvk_result read_linear(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    int v = 0;
    cvk_result r = cvk_read_enum(rd, value, path, "linear solver", linear_name, &v);
    if (r == CVK_SUCCESS)
        *(cvk_linear_solver*)dest = (cvk_linear_solver)v;
    return r;
}

/* The names a scene may give (NONE is the default, not a name to write). */
static const char* integrator_key_name(int v)
{
    return v >= 0 ? cvk_integrator_name((cvk_integrator)(v + 1)) : NULL;
}

static const char* damping_model_key_name(int v)
{
    return v >= 0 ? cvk_damping_model_name((cvk_damping_model)(v + 1)) : NULL;
}

static cvk_result read_integrator(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path,
                                  void* dest)
{
    (void)f;
    int v = 0;
    cvk_result r = cvk_read_enum(rd, value, path, "integrator", integrator_key_name, &v);
    if (r == CVK_SUCCESS)
        *(cvk_integrator*)dest = (cvk_integrator)(v + 1);
    return r;
}

static cvk_result read_damping_model(cvk_reader* rd, const cvk_field* f, json_t* value,
                                     const char* path, void* dest)
{
    (void)f;
    int v = 0;
    cvk_result r = cvk_read_enum(rd, value, path, "damping model", damping_model_key_name, &v);
    if (r == CVK_SUCCESS)
        *(cvk_damping_model*)dest = (cvk_damping_model)(v + 1);
    return r;
}

/* ---- a cloth's pins: [i, j] pairs on a grid, vertex indices on a mesh, and a box for either ---- */

static const cvk_field pin_pair_field = {.key = "pins", .read = cvk_read_uints, .count = 2, .min = 0};
static const cvk_field pin_vertex_field = {.key = "pins", .read = cvk_read_uint, .min = 0};

static cvk_result read_pin_pairs(cvk_reader* rd, json_t* value, size_t count, const char* path,
                                 cvk_cloth_desc* cloth)
{
    uint32_t (*pins)[2] = cvk_blocks_alloc(rd->blocks, count, sizeof *pins);
    if (!pins)
        return cvk_reader_fail_memory(rd);
    char element[CVK_KEY_PATH_MAX];
    for (size_t i = 0; i < count; i++) {
        cvk_json_join_index(element, path, i);
        cvk_result r = cvk_read_uints(rd, &pin_pair_field, json_array_get(value, i), element, pins[i]);
        if (r != CVK_SUCCESS)
            return r;
    }
    cloth->pins = (const uint32_t(*)[2])pins;
    cloth->pin_count = (uint32_t)count;
    return CVK_SUCCESS;
}

static cvk_result read_pin_vertices(cvk_reader* rd, json_t* value, size_t count, const char* path,
                                    cvk_cloth_desc* cloth)
{
    uint32_t* vertices = cvk_blocks_alloc(rd->blocks, count, sizeof *vertices);
    if (!vertices)
        return cvk_reader_fail_memory(rd);
    char element[CVK_KEY_PATH_MAX];
    for (size_t i = 0; i < count; i++) {
        json_t* pin = json_array_get(value, i);
        cvk_json_join_index(element, path, i);
        /* A pair among indices: say what element 0 made the reader expect. */
        if (json_is_array(pin))
            return cvk_reader_fail_type(rd, element, "a vertex index (a whole number, like element 0)", pin);
        cvk_result r = cvk_read_uint(rd, &pin_vertex_field, pin, element, &vertices[i]);
        if (r != CVK_SUCCESS)
            return r;
    }
    cloth->pin_vertices = vertices;
    cloth->pin_vertex_count = (uint32_t)count;
    return CVK_SUCCESS;
}

/* dest is the whole cloth. The first element says which form the array is: a pair ([i, j],
   for grids) or a vertex index (for meshes); validation then checks that the form fits the
   cloth. */
cvk_result cvk_read_pins(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    cvk_cloth_desc* cloth = dest;
    if (!json_is_array(value))
        return cvk_reader_fail_type(rd, path, "an array of [i, j] pairs or of vertex indices", value);
    size_t count = json_array_size(value);
    cloth->pins = NULL;
    cloth->pin_count = 0;
    cloth->pin_vertices = NULL;
    cloth->pin_vertex_count = 0;
    if (count == 0)
        return CVK_SUCCESS;
    if (count > UINT32_MAX)
        return cvk_reader_fail_at(rd, path, "more than %" PRIu32 " pins", UINT32_MAX);
    if (json_is_array(json_array_get(value, 0)))
        return read_pin_pairs(rd, value, count, path, cloth);
    return read_pin_vertices(rd, value, count, path, cloth);
}

static const cvk_field corner_field = {.key = "pin_box", .read = cvk_read_floats, .count = 3};

/* dest is the whole cloth: a box turns use_pin_box on. */
cvk_result cvk_read_pin_box(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    cvk_cloth_desc* cloth = dest;
    if (!json_is_array(value) || json_array_size(value) != 2)
        return cvk_reader_fail_type(rd, path, "[[xmin, ymin, zmin], [xmax, ymax, zmax]]", value);
    float* corners[2] = {cloth->pin_box.min, cloth->pin_box.max};
    char element[CVK_KEY_PATH_MAX];
    for (size_t i = 0; i < 2; i++) {
        cvk_json_join_index(element, path, i);
        cvk_result r = cvk_read_floats(rd, &corner_field, json_array_get(value, i), element, corners[i]);
        if (r != CVK_SUCCESS)
            return r;
    }
    cloth->use_pin_box = true;
    return CVK_SUCCESS;
}

/* ---- a mesh cloth's transform ---- */

/* One number scales every axis alike; it is checked here, where its key path is its own
   ("transform.scale", not the "transform.scale.0" validation would name). */
static cvk_result read_scale(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    float* scale = dest;
    if (json_is_array(value))
        return cvk_read_floats(rd, f, value, path, dest);
    if (!json_is_number(value) && !cvk_json_is_nonfinite(value))
        return cvk_reader_fail_type(rd, path, "a number or an array of 3 numbers", value);
    cvk_result r = cvk_read_float(rd, f, value, path, &scale[0]);
    if (r != CVK_SUCCESS)
        return r;
    cvk_scene_issue issue;
    if (!cvk_check_scale(&issue, path, scale[0]))
        return cvk_reader_fail_problem(rd, issue.path, issue.problem);
    scale[1] = scale[2] = scale[0];
    return CVK_SUCCESS;
}

static const cvk_field stiffness_fields[] = {
    {.key = "structural", .read = cvk_read_float, .offset = offsetof(cvk_stiffness, structural)},
    {.key = "shear", .read = cvk_read_float, .offset = offsetof(cvk_stiffness, shear)},
    {.key = "bend", .read = cvk_read_float, .offset = offsetof(cvk_stiffness, bend)},
};
static const cvk_table stiffness_table = FIELDS(stiffness_fields);

static const cvk_field transform_fields[] = {
    {.key = "scale", .read = read_scale, .offset = offsetof(cvk_transform, scale), .count = 3},
    {.key = "rotation", .read = cvk_read_floats, .offset = offsetof(cvk_transform, rotation), .count = 4},
    {.key = "translation", .read = cvk_read_floats, .offset = offsetof(cvk_transform, translation), .count = 3},
};
static const cvk_table transform_table = FIELDS(transform_fields);

static const cvk_field aero_fields[] = {
    {.key = "drag", .read = cvk_read_float, .offset = offsetof(cvk_aero_desc, drag)},
    {.key = "lift", .read = cvk_read_float, .offset = offsetof(cvk_aero_desc, lift)},
    {.key = "friction", .read = cvk_read_float, .offset = offsetof(cvk_aero_desc, friction)},
};
static const cvk_table aero_table = FIELDS(aero_fields);
static const cvk_field tearing_fields[] = {
    {.key = "max_stretch", .read = cvk_read_float, .offset = offsetof(cvk_tearing_desc, max_stretch)},
};
static const cvk_table tearing_table = FIELDS(tearing_fields);

/* dest is the whole cloth: a texture named in the material block is marked so (messages name
   cloths.N.material.texture). */
static cvk_result read_material_texture(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path,
                                        void* dest)
{
    cvk_cloth_desc* cloth = dest;
    cloth->material_texture = true;
    return cvk_read_path(rd, f, value, path, &cloth->texture);
}

/* The cloth's "material" block: its fields are the cloth's own (color and texture are the same
   as the cloth's keys of those names). */
static const cvk_field material_fields[] = {
    {.key = "color", .read = cvk_read_floats, .offset = offsetof(cvk_cloth_desc, color), .count = 3},
    {.key = "back_color", .read = cvk_read_floats, .offset = offsetof(cvk_cloth_desc, back_color), .count = 3},
    {.key = "texture", .read = read_material_texture, .offset = 0},
    {.key = "sheen", .read = cvk_read_float, .offset = offsetof(cvk_cloth_desc, sheen)},
    {.key = "roughness", .read = cvk_read_float, .offset = offsetof(cvk_cloth_desc, roughness)},
    {.key = "thickness", .read = cvk_read_float, .offset = offsetof(cvk_cloth_desc, thickness)},
    {.key = "normal_map", .read = cvk_read_path, .offset = offsetof(cvk_cloth_desc, normal_map)},
    {.key = "normal_strength", .read = cvk_read_float, .offset = offsetof(cvk_cloth_desc, normal_strength)},
};
static const cvk_table material_table = FIELDS(material_fields);

static const cvk_field cloth_fields[] = {
    {.key = "name", .read = cvk_read_string, .offset = offsetof(cvk_cloth_desc, name)},
    {.key = "grid", .read = cvk_read_uints, .offset = offsetof(cvk_cloth_desc, grid), .count = 2, .min = 1},
    {.key = "size", .read = cvk_read_floats, .offset = offsetof(cvk_cloth_desc, size), .count = 2},
    {.key = "origin", .read = cvk_read_floats, .offset = offsetof(cvk_cloth_desc, origin), .count = 3},
    {.key = "u_axis", .read = cvk_read_floats, .offset = offsetof(cvk_cloth_desc, u_axis), .count = 3},
    {.key = "v_axis", .read = cvk_read_floats, .offset = offsetof(cvk_cloth_desc, v_axis), .count = 3},
    {.key = "mesh", .read = cvk_read_path, .offset = offsetof(cvk_cloth_desc, mesh)},
    {.key = "transform", .read = cvk_read_nested, .offset = offsetof(cvk_cloth_desc, transform),
     .nested = &transform_table},
    {.key = "rest_scale", .read = cvk_read_float, .offset = offsetof(cvk_cloth_desc, rest_scale)},
    {.key = "mass", .read = cvk_read_float, .offset = offsetof(cvk_cloth_desc, mass)},
    {.key = "density", .read = cvk_read_float, .offset = offsetof(cvk_cloth_desc, density)},
    {.key = "stiffness", .read = cvk_read_nested, .offset = offsetof(cvk_cloth_desc, stiffness),
     .nested = &stiffness_table},
    {.key = "pins", .read = cvk_read_pins, .offset = 0},
    {.key = "pin_box", .read = cvk_read_pin_box, .offset = 0},
    {.key = "color", .read = cvk_read_floats, .offset = offsetof(cvk_cloth_desc, color), .count = 3},
    {.key = "texture", .read = cvk_read_path, .offset = offsetof(cvk_cloth_desc, texture)},
    {.key = "texture_scale", .read = cvk_read_floats, .offset = offsetof(cvk_cloth_desc, texture_scale), .count = 2},
    {.key = "velocity", .read = cvk_read_floats, .offset = offsetof(cvk_cloth_desc, velocity), .count = 3},
    {.key = "tethers", .read = cvk_read_float, .offset = offsetof(cvk_cloth_desc, tethers)},
    {.key = "aero", .read = cvk_read_nested, .offset = offsetof(cvk_cloth_desc, aero), .nested = &aero_table},
    {.key = "tearing", .read = cvk_read_nested, .offset = offsetof(cvk_cloth_desc, tearing), .nested = &tearing_table},
    {.key = "material", .read = cvk_read_nested, .offset = 0, .nested = &material_table},
};
static const cvk_table cloth_table = FIELDS(cloth_fields);

/* dest is the whole scene: cloths and cloth_count go together. */
static cvk_result read_cloths(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    cvk_scene_desc* desc = dest;
    if (!json_is_array(value))
        return cvk_reader_fail_type(rd, path, "an array of cloth objects", value);
    size_t count = json_array_size(value);
    if (count == 0)
        return CVK_SUCCESS; /* validation says that a scene needs a cloth */
    if (count > UINT32_MAX)
        return cvk_reader_fail_at(rd, path, "more than %" PRIu32 " cloths", UINT32_MAX);
    cvk_cloth_desc* cloths = cvk_blocks_alloc(rd->blocks, count, sizeof *cloths);
    if (!cloths)
        return cvk_reader_fail_memory(rd);
    char element[CVK_KEY_PATH_MAX];
    for (size_t i = 0; i < count; i++) {
        cvk_json_join_index(element, path, i);
        cloths[i] = cvk_default_cloth_desc();
        cvk_result r = cvk_read_object(rd, &cloth_table, json_array_get(value, i), element, &cloths[i]);
        if (r != CVK_SUCCESS)
            return r;
    }
    desc->cloths = cloths;
    desc->cloth_count = (uint32_t)count;
    return CVK_SUCCESS;
}

/* ---- collisions: the scene's defaults and the colliders ---- */

static const cvk_field collision_fields[] = {
    {.key = "self", .read = cvk_read_bool, .offset = offsetof(cvk_collision_desc, self)},
    {.key = "thickness", .read = cvk_read_float, .offset = offsetof(cvk_collision_desc, thickness)},
    {.key = "radius", .read = cvk_read_float, .offset = offsetof(cvk_collision_desc, radius)},
    {.key = "friction", .read = cvk_read_float, .offset = offsetof(cvk_collision_desc, friction)},
    {.key = "static_friction", .read = cvk_read_float, .offset = offsetof(cvk_collision_desc, static_friction)},
    {.key = "allow_intersecting_start", .read = cvk_read_bool,
     .offset = offsetof(cvk_collision_desc, allow_intersecting_start)},
    {.key = "detection_interval", .read = cvk_read_uint,
     .offset = offsetof(cvk_collision_desc, detection_interval)},
    /* No effect (cvk_collision_desc): read so that old scenes load, and named in the notes. */
    {.key = "detect_every", .read = cvk_read_uint, .offset = offsetof(cvk_collision_desc, detect_every)},
    {.key = "exclusion", .read = cvk_read_float, .offset = offsetof(cvk_collision_desc, exclusion)},
    {.key = "edges", .read = cvk_read_bool, .offset = offsetof(cvk_collision_desc, edges)},
};
static const cvk_table collision_table = FIELDS(collision_fields);

static const cvk_field keyframe_fields[] = {
    {.key = "time", .read = cvk_read_float, .offset = offsetof(cvk_keyframe, time),
     .required = "a keyframe needs its time"},
    {.key = "translation", .read = cvk_read_floats, .offset = offsetof(cvk_keyframe, translation), .count = 3},
    {.key = "rotation", .read = cvk_read_floats, .offset = offsetof(cvk_keyframe, rotation), .count = 4},
};
static const cvk_table keyframe_table = FIELDS(keyframe_fields);

/* dest is the collider's motion: keyframes and keyframe_count go together. */
cvk_result cvk_read_keyframes(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    cvk_motion* motion = dest;
    if (!json_is_array(value))
        return cvk_reader_fail_type(rd, path, "an array of keyframe objects", value);
    size_t count = json_array_size(value);
    motion->keyframes = NULL;
    motion->keyframe_count = 0;
    if (count == 0)
        return CVK_SUCCESS;
    if (count > UINT32_MAX)
        return cvk_reader_fail_at(rd, path, "more than %" PRIu32 " keyframes", UINT32_MAX);
    cvk_keyframe* keyframes = cvk_blocks_alloc(rd->blocks, count, sizeof *keyframes);
    if (!keyframes)
        return cvk_reader_fail_memory(rd);
    char element[CVK_KEY_PATH_MAX];
    for (size_t i = 0; i < count; i++) {
        cvk_json_join_index(element, path, i);
        keyframes[i] = (cvk_keyframe){.rotation = {1.0f, 0.0f, 0.0f, 0.0f}};
        cvk_result r = cvk_read_object(rd, &keyframe_table, json_array_get(value, i), element, &keyframes[i]);
        if (r != CVK_SUCCESS)
            return r;
    }
    motion->keyframes = keyframes;
    motion->keyframe_count = (uint32_t)count;
    return CVK_SUCCESS;
}

/* A negative coefficient means "the scene's" in the C API; a scene file leaves the key out
   instead, so there it is a mistake. A non-finite one is left to validation to name. */
static cvk_result read_coefficient(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    float v = 0.0f;
    cvk_result r = cvk_read_float(rd, f, value, path, &v);
    if (r != CVK_SUCCESS)
        return r;
    if (v < 0.0f && isfinite(v))
        return cvk_reader_fail_at(rd, path, "must be at least 0, got %s (leave it out for collision.%s)", cvk_float_text(v).text, f->key);
    *(float*)dest = v;
    return CVK_SUCCESS;
}

static const char* collider_type_name(int v)
{
    return cvk_collider_type_name((cvk_collider_type)v);
}

static cvk_result read_collider_type(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path,
                                     void* dest)
{
    (void)f;
    int v = 0;
    cvk_result r = cvk_read_enum(rd, value, path, "collider type", collider_type_name, &v);
    if (r == CVK_SUCCESS)
        *(cvk_collider_type*)dest = (cvk_collider_type)v;
    return r;
}

#define COLLIDER(field) offsetof(cvk_collider_desc, field)

/* The collider's "material" block: how the renderer draws it (color is the same as the
   collider's key of that name; texture and texture_scale are only here). */
static const cvk_field collider_material_fields[] = {
    {.key = "color", .read = cvk_read_floats, .offset = COLLIDER(color), .count = 3},
    {.key = "roughness", .read = cvk_read_float, .offset = COLLIDER(roughness)},
    {.key = "texture", .read = cvk_read_path, .offset = COLLIDER(texture)},
    {.key = "texture_scale", .read = cvk_read_float, .offset = COLLIDER(texture_scale)},
};
static const cvk_table collider_material_table = FIELDS(collider_material_fields);

/* The keys of every collider; each type's table adds its shape's. */
static const cvk_field collider_fields[] = {
    {.key = "type", .read = read_collider_type, .offset = COLLIDER(type)},
    {.key = "name", .read = cvk_read_string, .offset = COLLIDER(name)},
    {.key = "friction", .read = read_coefficient, .offset = COLLIDER(friction)},
    {.key = "static_friction", .read = read_coefficient, .offset = COLLIDER(static_friction)},
    {.key = "color", .read = cvk_read_floats, .offset = COLLIDER(color), .count = 3},
    {.key = "keyframes", .read = cvk_read_keyframes, .offset = COLLIDER(motion)},
    {.key = "loop", .read = cvk_read_bool, .offset = COLLIDER(motion) + offsetof(cvk_motion, loop)},
    {.key = "material", .read = cvk_read_nested, .offset = 0, .nested = &collider_material_table},
};
static const cvk_table collider_table = FIELDS(collider_fields);

static const cvk_field plane_fields[] = {
    {.key = "point", .read = cvk_read_floats, .offset = COLLIDER(point), .count = 3},
    {.key = "normal", .read = cvk_read_floats, .offset = COLLIDER(normal), .count = 3},
};
static const cvk_field sphere_fields[] = {
    {.key = "center", .read = cvk_read_floats, .offset = COLLIDER(center), .count = 3},
    {.key = "radius", .read = cvk_read_float, .offset = COLLIDER(radius)},
};
static const cvk_field box_fields[] = {
    {.key = "center", .read = cvk_read_floats, .offset = COLLIDER(center), .count = 3},
    {.key = "half_extents", .read = cvk_read_floats, .offset = COLLIDER(half_extents), .count = 3},
    {.key = "rotation", .read = cvk_read_floats, .offset = COLLIDER(rotation), .count = 4},
};
static const cvk_field capsule_fields[] = {
    {.key = "a", .read = cvk_read_floats, .offset = COLLIDER(a), .count = 3},
    {.key = "b", .read = cvk_read_floats, .offset = COLLIDER(b), .count = 3},
    {.key = "radius", .read = cvk_read_float, .offset = COLLIDER(radius)},
};
/* "a" is the funnel's growth length here, the segment's first end on a capsule. */
static const cvk_field funnel_fields[] = {
    {.key = "apex", .read = cvk_read_floats, .offset = COLLIDER(apex), .count = 3},
    {.key = "a", .read = cvk_read_float, .offset = COLLIDER(funnel_a)},
    {.key = "height", .read = cvk_read_float, .offset = COLLIDER(height)},
};
static const cvk_field mesh_collider_fields[] = {
    {.key = "file", .read = cvk_read_path, .offset = COLLIDER(file)},
    {.key = "transform", .read = cvk_read_nested, .offset = COLLIDER(transform), .nested = &transform_table},
};

#define SHAPE_FIELDS(array, name) \
    {.fields = array, .count = sizeof array / sizeof array[0], .owner = name, .shared = &collider_table}

/* Indexed by cvk_collider_type. */
static const cvk_table shape_tables[CVK_COLLIDER_TYPE_COUNT] = {
    [CVK_COLLIDER_PLANE] = SHAPE_FIELDS(plane_fields, "a plane collider"),
    [CVK_COLLIDER_SPHERE] = SHAPE_FIELDS(sphere_fields, "a sphere collider"),
    [CVK_COLLIDER_BOX] = SHAPE_FIELDS(box_fields, "a box collider"),
    [CVK_COLLIDER_CAPSULE] = SHAPE_FIELDS(capsule_fields, "a capsule collider"),
    [CVK_COLLIDER_FUNNEL] = SHAPE_FIELDS(funnel_fields, "a funnel collider"),
    [CVK_COLLIDER_MESH] = SHAPE_FIELDS(mesh_collider_fields, "a mesh collider"),
};

/* The type says which keys the object may have, so it is read first. */
static cvk_result read_collider(cvk_reader* rd, json_t* value, const char* path, cvk_collider_desc* collider)
{
    if (!json_is_object(value))
        return cvk_reader_fail_type(rd, path, "a collider object", value);
    char type_path[CVK_KEY_PATH_MAX];
    cvk_json_join_key(type_path, path, "type");
    json_t* type = json_object_get(value, "type");
    if (!type) {
        char names[128];
        cvk_list_names(collider_type_name, names, sizeof names);
        return cvk_reader_fail_at(rd, type_path, "missing; a collider needs its type: %s", names);
    }
    *collider = cvk_default_collider_desc();
    cvk_result r = read_collider_type(rd, NULL, type, type_path, &collider->type);
    if (r != CVK_SUCCESS)
        return r;
    return cvk_read_object(rd, &shape_tables[collider->type], value, path, collider);
}

/* dest is the whole scene: colliders and collider_count go together. */
static cvk_result read_colliders(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    cvk_scene_desc* desc = dest;
    if (!json_is_array(value))
        return cvk_reader_fail_type(rd, path, "an array of collider objects", value);
    size_t count = json_array_size(value);
    desc->colliders = NULL;
    desc->collider_count = 0;
    if (count == 0)
        return CVK_SUCCESS;
    if (count > UINT32_MAX)
        return cvk_reader_fail_at(rd, path, "more than %" PRIu32 " colliders", UINT32_MAX);
    cvk_collider_desc* colliders = cvk_blocks_alloc(rd->blocks, count, sizeof *colliders);
    if (!colliders)
        return cvk_reader_fail_memory(rd);
    char element[CVK_KEY_PATH_MAX];
    for (size_t i = 0; i < count; i++) {
        cvk_json_join_index(element, path, i);
        cvk_result r = read_collider(rd, json_array_get(value, i), element, &colliders[i]);
        if (r != CVK_SUCCESS)
            return r;
    }
    desc->colliders = colliders;
    desc->collider_count = (uint32_t)count;
    return CVK_SUCCESS;
}

/* solver.tolerance and solver.max_iterations: 0 is the description's "the method's default",
   not a value to write (lib/scene/scene.c, check_stopping, has the rest of the rule). */
static cvk_result read_tolerance(cvk_reader* rd, const cvk_field* f, json_t* value,
                                 const char* path, void* dest)
{
    cvk_result r = cvk_read_float(rd, f, value, path, dest);
    if (r == CVK_SUCCESS && *(float*)dest == 0.0f)
        return cvk_reader_fail_at(rd, path, "must be greater than 0 and less than 1, got 0");
    return r;
}

static cvk_result read_max_iterations(cvk_reader* rd, const cvk_field* f, json_t* value,
                                      const char* path, void* dest)
{
    cvk_result r = cvk_read_uint(rd, f, value, path, dest);
    if (r == CVK_SUCCESS && *(uint32_t*)dest < f->min)
        return cvk_reader_fail_at(rd, path, "must be at least %" PRIu32 ", got 0", f->min);
    return r;
}

static const cvk_field solver_fields[] = {
    {.key = "method", .read = read_method, .offset = offsetof(cvk_solver_desc, method)},
    {.key = "linear", .read = read_linear, .offset = offsetof(cvk_solver_desc, linear)},
    {.key = "outer_iterations", .read = cvk_read_uint, .offset = offsetof(cvk_solver_desc, outer_iterations),
     .min = 1},
    {.key = "inner_iterations", .read = cvk_read_uint, .offset = offsetof(cvk_solver_desc, inner_iterations),
     .min = 1},
    {.key = "omega", .read = cvk_read_float, .offset = offsetof(cvk_solver_desc, omega)},
    {.key = "chebyshev_rho", .read = cvk_read_float, .offset = offsetof(cvk_solver_desc, chebyshev_rho)},
    {.key = "chebyshev_delay", .read = cvk_read_uint, .offset = offsetof(cvk_solver_desc, chebyshev_delay)},
    {.key = "tolerance", .read = read_tolerance, .offset = offsetof(cvk_solver_desc, tolerance)},
    {.key = "max_iterations", .read = read_max_iterations,
     .offset = offsetof(cvk_solver_desc, max_iterations), .min = 1},
    {.key = "kd", .read = cvk_read_float, .offset = offsetof(cvk_solver_desc, kd)},
    {.key = "integrator", .read = read_integrator, .offset = offsetof(cvk_solver_desc, integrator)},
    {.key = "damping_model", .read = read_damping_model,
     .offset = offsetof(cvk_solver_desc, damping_model)},
    {.key = "tether_every", .read = cvk_read_uint, .offset = offsetof(cvk_solver_desc, tether_every)},
    {.key = "strain_limit", .read = cvk_read_float, .offset = offsetof(cvk_solver_desc, strain_limit)},
    {.key = "fuse", .read = read_fuse, .offset = offsetof(cvk_solver_desc, fuse)},
};
static const cvk_table solver_table = FIELDS(solver_fields);

/* dest is the whole render description: an explicit eye, target or ground height replaces the
   automatic one. */
static cvk_result read_eye(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    cvk_render_desc* render = dest;
    render->auto_eye = false;
    return cvk_read_floats(rd, f, value, path, render->eye);
}

static cvk_result read_target(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    cvk_render_desc* render = dest;
    render->auto_target = false;
    return cvk_read_floats(rd, f, value, path, render->target);
}

static cvk_result read_ground_height(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path,
                                     void* dest)
{
    cvk_render_desc* render = dest;
    render->auto_ground_height = false;
    return cvk_read_float(rd, f, value, path, &render->ground_height);
}

static const cvk_field fit_fields[] = {
    {.key = "margin", .read = cvk_read_float, .offset = offsetof(cvk_render_desc, fit_margin)},
};
static const cvk_table fit_table = FIELDS(fit_fields);

/* render.fit: true or false, or an object of options (fitting, with its margin). dest is the
   render description. */
static cvk_result read_fit(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    cvk_render_desc* render = dest;
    if (json_is_boolean(value)) {
        render->fit = json_is_true(value);
        return CVK_SUCCESS;
    }
    if (!json_is_object(value))
        return cvk_reader_fail_type(rd, path, "true, false or an object such as {\"margin\": 0.1}", value);
    render->fit = true;
    return cvk_read_object(rd, &fit_table, value, path, render);
}

static const cvk_field light_fields[] = {
    {.key = "direction", .read = cvk_read_floats, .offset = offsetof(cvk_light, direction), .count = 3},
    {.key = "color", .read = cvk_read_floats, .offset = offsetof(cvk_light, color), .count = 3},
};
static const cvk_table light_table = FIELDS(light_fields);

static const cvk_field camera_keyframe_fields[] = {
    {.key = "time", .read = cvk_read_float, .offset = offsetof(cvk_camera_keyframe, time),
     .required = "a camera keyframe needs its time"},
    {.key = "eye", .read = cvk_read_floats, .offset = offsetof(cvk_camera_keyframe, eye), .count = 3,
     .required = "a camera keyframe needs its eye"},
    {.key = "target", .read = cvk_read_floats, .offset = offsetof(cvk_camera_keyframe, target), .count = 3,
     .required = "a camera keyframe needs its target"},
};
static const cvk_table camera_keyframe_table = FIELDS(camera_keyframe_fields);

/* dest is the render description: camera_keyframes and camera_keyframe_count go together. */
static cvk_result read_camera_keyframes(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path,
                                        void* dest)
{
    (void)f;
    cvk_render_desc* render = dest;
    if (!json_is_array(value))
        return cvk_reader_fail_type(rd, path, "an array of camera keyframe objects", value);
    size_t count = json_array_size(value);
    render->camera_keyframes = NULL;
    render->camera_keyframe_count = 0;
    if (count == 0)
        return CVK_SUCCESS;
    if (count > UINT32_MAX)
        return cvk_reader_fail_at(rd, path, "more than %" PRIu32 " keyframes", UINT32_MAX);
    cvk_camera_keyframe* keyframes = cvk_blocks_alloc(rd->blocks, count, sizeof *keyframes);
    if (!keyframes)
        return cvk_reader_fail_memory(rd);
    char element[CVK_KEY_PATH_MAX];
    for (size_t i = 0; i < count; i++) {
        cvk_json_join_index(element, path, i);
        keyframes[i] = (cvk_camera_keyframe){0};
        cvk_result r = cvk_read_object(rd, &camera_keyframe_table, json_array_get(value, i), element, &keyframes[i]);
        if (r != CVK_SUCCESS)
            return r;
    }
    render->camera_keyframes = keyframes;
    render->camera_keyframe_count = (uint32_t)count;
    return CVK_SUCCESS;
}

static const cvk_field render_fields[] = {
    {.key = "size", .read = cvk_read_uints, .offset = offsetof(cvk_render_desc, size), .count = 2, .min = 1},
    {.key = "eye", .read = read_eye, .offset = 0, .count = 3},
    {.key = "target", .read = read_target, .offset = 0, .count = 3},
    {.key = "up", .read = cvk_read_floats, .offset = offsetof(cvk_render_desc, up), .count = 3},
    {.key = "fov_y", .read = cvk_read_float, .offset = offsetof(cvk_render_desc, fov_y)},
    {.key = "key", .read = cvk_read_nested, .offset = offsetof(cvk_render_desc, key), .nested = &light_table},
    {.key = "fill", .read = cvk_read_nested, .offset = offsetof(cvk_render_desc, fill), .nested = &light_table},
    {.key = "ambient", .read = cvk_read_floats, .offset = offsetof(cvk_render_desc, ambient), .count = 3},
    {.key = "background", .read = cvk_read_floats, .offset = offsetof(cvk_render_desc, background), .count = 3},
    {.key = "ground", .read = cvk_read_bool, .offset = offsetof(cvk_render_desc, ground)},
    {.key = "ground_height", .read = read_ground_height, .offset = 0},
    {.key = "ground_color", .read = cvk_read_floats, .offset = offsetof(cvk_render_desc, ground_color), .count = 3},
    {.key = "shadow_map_size", .read = cvk_read_uint, .offset = offsetof(cvk_render_desc, shadow_map_size),
     .min = 16},
    {.key = "samples", .read = cvk_read_uint, .offset = offsetof(cvk_render_desc, samples), .min = 1},
    {.key = "wireframe", .read = cvk_read_bool, .offset = offsetof(cvk_render_desc, wireframe)},
    {.key = "camera_keyframes", .read = read_camera_keyframes, .offset = 0},
    {.key = "camera_loop", .read = cvk_read_bool, .offset = offsetof(cvk_render_desc, camera_loop)},
    {.key = "soft_shadows", .read = cvk_read_bool, .offset = offsetof(cvk_render_desc, soft_shadows)},
    {.key = "key_angle", .read = cvk_read_float, .offset = offsetof(cvk_render_desc, key_angle)},
    {.key = "sky_light", .read = cvk_read_bool, .offset = offsetof(cvk_render_desc, sky_light)},
    {.key = "ao", .read = cvk_read_bool, .offset = offsetof(cvk_render_desc, ao)},
    {.key = "ao_radius", .read = cvk_read_float, .offset = offsetof(cvk_render_desc, ao_radius)},
    {.key = "tone_map", .read = cvk_read_bool, .offset = offsetof(cvk_render_desc, tone_map)},
    {.key = "smooth", .read = cvk_read_uint, .offset = offsetof(cvk_render_desc, smooth)},
    {.key = "fit", .read = read_fit, .offset = 0},
    {.key = "overlay", .read = cvk_read_bool, .offset = offsetof(cvk_render_desc, overlay)},
    {.key = "vertex_lighting", .read = cvk_read_float, .offset = offsetof(cvk_render_desc, vertex_lighting)},
};
static const cvk_table render_table = FIELDS(render_fields);

static const cvk_field scene_fields[] = {
    {.key = "name", .read = cvk_read_string, .offset = offsetof(cvk_scene_desc, name)},
    {.key = "dt", .read = cvk_read_float, .offset = offsetof(cvk_scene_desc, dt)},
    {.key = "substeps", .read = cvk_read_uint, .offset = offsetof(cvk_scene_desc, substeps), .min = 1},
    {.key = "frames", .read = cvk_read_uint, .offset = offsetof(cvk_scene_desc, frames), .min = 1},
    {.key = "integrate", .read = cvk_read_bool, .offset = offsetof(cvk_scene_desc, integrate)},
    {.key = "gravity", .read = cvk_read_floats, .offset = offsetof(cvk_scene_desc, gravity), .count = 3},
    {.key = "damping", .read = cvk_read_float, .offset = offsetof(cvk_scene_desc, damping)},
    {.key = "solver", .read = cvk_read_nested, .offset = offsetof(cvk_scene_desc, solver), .nested = &solver_table},
    {.key = "cloths", .read = read_cloths, .offset = 0, .required = "a scene needs at least one cloth"},
    {.key = "render", .read = cvk_read_nested, .offset = offsetof(cvk_scene_desc, render), .nested = &render_table},
    {.key = "collision", .read = cvk_read_nested, .offset = offsetof(cvk_scene_desc, collision),
     .nested = &collision_table},
    {.key = "colliders", .read = read_colliders, .offset = 0},
    {.key = "attachments", .read = cvk_read_attachments, .offset = 0},
    {.key = "wind", .read = cvk_read_wind, .offset = offsetof(cvk_scene_desc, wind), .nested = &cvk_wind_table},
    {.key = "air_density", .read = cvk_read_float, .offset = offsetof(cvk_scene_desc, air_density)},
    {.key = "instances", .read = cvk_read_instances, .offset = 0},
};
const cvk_table cvk_scene_table = FIELDS(scene_fields);
