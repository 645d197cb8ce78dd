/* The scene keys of things that change over time: attachments (a cloth's particles moved by
   keyframes) and the air (wind, gusts). The tables of lib/scene/scene_json.c name these readers. */
#include <inttypes.h>
#include <stddef.h>
#include <string.h>

#include "scene/scene_read.h"

/* ---- attachments: a cloth's particles moved by keyframes ---- */

/* dest is the attachment: "pins" and "pin_box" are read as a cloth's are. */
static cvk_result read_attachment_pins(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path,
                                       void* dest)
{
    cvk_attachment_desc* a = dest;
    cvk_cloth_desc pins = cvk_attachment_pins_as_cloth(&(cvk_cloth_desc){0}, a);
    cvk_result r = strcmp(f->key, "pins") == 0 ? cvk_read_pins(rd, f, value, path, &pins)
                                               : cvk_read_pin_box(rd, f, value, path, &pins);
    if (r != CVK_SUCCESS)
        return r;
    a->pins = pins.pins;
    a->pin_count = pins.pin_count;
    a->pin_vertices = pins.pin_vertices;
    a->pin_vertex_count = pins.pin_vertex_count;
    a->use_pin_box = pins.use_pin_box;
    a->pin_box = pins.pin_box;
    return CVK_SUCCESS;
}

#define ATTACHMENT(field) offsetof(cvk_attachment_desc, field)
static const cvk_field attachment_fields[] = {
    {.key = "cloth", .read = cvk_read_uint, .offset = ATTACHMENT(cloth), .min = 0},
    {.key = "pins", .read = read_attachment_pins, .offset = 0},
    {.key = "pin_box", .read = read_attachment_pins, .offset = 0},
    {.key = "keyframes", .read = cvk_read_keyframes, .offset = ATTACHMENT(motion)},
    {.key = "loop", .read = cvk_read_bool, .offset = ATTACHMENT(motion) + offsetof(cvk_motion, loop)},
};
static const cvk_table attachment_table = FIELDS(attachment_fields);

/* dest is the whole scene: attachments and attachment_count go together. */
cvk_result cvk_read_attachments(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path,
                                   void* dest)
{
    (void)f;
    cvk_scene_desc* desc = dest;
    if (!json_is_array(value))
        return cvk_reader_fail_type(rd, path, "an array of attachment objects", value);
    size_t count = json_array_size(value);
    desc->attachments = NULL;
    desc->attachment_count = 0;
    if (count == 0)
        return CVK_SUCCESS;
    if (count > UINT32_MAX)
        return cvk_reader_fail_at(rd, path, "more than %" PRIu32 " attachments", UINT32_MAX);
    cvk_attachment_desc* attachments = cvk_blocks_alloc(rd->blocks, count, sizeof *attachments);
    if (!attachments)
        return cvk_reader_fail_memory(rd);
    char element[CVK_KEY_PATH_MAX];
    for (size_t i = 0; i < count; i++) {
        cvk_json_join_index(element, path, i);
        attachments[i] = cvk_default_attachment_desc();
        cvk_result r = cvk_read_object(rd, &attachment_table, json_array_get(value, i), element, &attachments[i]);
        if (r != CVK_SUCCESS)
            return r;
    }
    desc->attachments = attachments;
    desc->attachment_count = (uint32_t)count;
    return CVK_SUCCESS;
}

/* ---- the air: wind and gusts ---- */

static const cvk_field gusts_fields[] = {
    {.key = "amplitude", .read = cvk_read_float, .offset = offsetof(cvk_gusts_desc, amplitude)},
    {.key = "period", .read = cvk_read_float, .offset = offsetof(cvk_gusts_desc, period)},
    {.key = "jitter", .read = cvk_read_float, .offset = offsetof(cvk_gusts_desc, jitter)},
};
static const cvk_table gusts_table = FIELDS(gusts_fields);

static const cvk_field wind_fields[] = {
    {.key = "velocity", .read = cvk_read_floats, .offset = offsetof(cvk_wind_desc, velocity), .count = 3},
    {.key = "gusts", .read = cvk_read_nested, .offset = offsetof(cvk_wind_desc, gusts), .nested = &gusts_table},
};
const cvk_table cvk_wind_table = FIELDS(wind_fields);

/* dest is the wind: a "wind" block turns the air on. */
cvk_result cvk_read_wind(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    cvk_wind_desc* wind = dest;
    wind->enabled = true;
    return cvk_read_nested(rd, f, value, path, dest);
}
