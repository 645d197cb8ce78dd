/* JSON values into C structs, key by key, from field tables: a block of the scene format is a
   table of its keys, each with the reader for its kind of value and where the value goes, so a
   new block is a new table, not new parsing code, and an unknown key fails by construction.
   Every message starts with the source (the file name), then the key path (the same path --set
   takes), then the problem. */
#ifndef CVK_SCENE_READ_H
#define CVK_SCENE_READ_H

#include "scene/scene.h"

#include <jansson.h>

/* The allocations a description points into, freed together. */
typedef struct cvk_blocks {
    void** items;
    size_t count;
    size_t capacity;
} cvk_blocks;

/* Keeps block (which may be NULL) and returns it; NULL, with block freed, when out of memory. */
void* cvk_blocks_keep(cvk_blocks* blocks, void* block);
/* calloc kept in blocks. */
void* cvk_blocks_alloc(cvk_blocks* blocks, size_t count, size_t size);
void cvk_blocks_free(cvk_blocks* blocks);

/* State of one conversion: where allocations and messages go, and which key paths the
   overrides wrote. */
typedef struct cvk_reader {
    cvk_blocks* blocks;                  /* strings and arrays the description points to */
    const char* source;                  /* file name (or source_name) that starts every message */
    size_t folder_length;                /* source[0, folder_length) is the folder, '/' included, that
                                            relative paths are relative to; 0: paths kept as written */
    char (*set_paths)[CVK_KEY_PATH_MAX]; /* key paths the overrides wrote, indices normalised */
    uint32_t set_count;
    cvk_error* error;
} cvk_reader;

/* ---- messages: "source: path: problem", with " (from --set)" after a path an override wrote ---- */

cvk_result cvk_reader_fail_problem(cvk_reader* rd, const char* path, const char* problem);
cvk_result cvk_reader_fail_at(cvk_reader* rd, const char* path, const char* format, ...)
    __attribute__((format(printf, 3, 4)));
/* "expected <expected>, got <what value is>" */
cvk_result cvk_reader_fail_type(cvk_reader* rd, const char* path, const char* expected, const json_t* value);
cvk_result cvk_reader_fail_memory(cvk_reader* rd);
/* What a reader found where it expected something else: "a string", "an array of 2", "NaN". */
const char* cvk_json_describe(const json_t* value, char* buffer, size_t size);
/* true for a string that stands for a bare NaN or Infinity of the text (see cvk_json_parse). */
bool cvk_json_is_nonfinite(const json_t* value);

/* "path.key" ("key" when path is empty) and "path.index". */
void cvk_json_join_key(char out[CVK_KEY_PATH_MAX], const char* path, const char* key);
void cvk_json_join_index(char out[CVK_KEY_PATH_MAX], const char* path, size_t index);

/* ---- tables ---- */

typedef struct cvk_field cvk_field;
typedef struct cvk_table cvk_table;
/* Reads value (found at key path `path`) into dest, the destination struct plus the field's
   offset. */
typedef cvk_result (*cvk_read_fn)(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path,
                                  void* dest);

struct cvk_field {
    const char* key;
    cvk_read_fn read;
    size_t offset;            /* where the value goes in the destination struct */
    uint32_t count;           /* array readers: number of elements */
    uint32_t min;             /* whole-number readers: least valid value, named when a value is negative */
    const cvk_table* nested;  /* object readers: the nested object's keys */
    const char* required;     /* set: the key must be present, and this says why */
};

struct cvk_table {
    const cvk_field* fields;
    size_t count;
    const char* owner;        /* set: unknown keys are named as not keys of this ("a box
                                 collider"), for objects whose keys depend on a value in them */
    const cvk_table* shared;  /* set: its keys belong to this table too, listed first */
};

/* ---- value readers: one per kind of key ---- */

cvk_result cvk_read_string(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest);
/* A file's path: a relative one is joined to the reader's folder (the scene file's), so that it
   names the same file from any working directory; an absolute one, or one read without a
   folder, is kept as written. */
cvk_result cvk_read_path(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest);
cvk_result cvk_read_bool(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest);
/* A float; out of float range becomes ±inf, which validation reports as not finite. */
cvk_result cvk_read_float(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest);
/* A uint32_t; f->min is named when the value is negative. */
cvk_result cvk_read_uint(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest);
/* Exactly f->count elements. */
cvk_result cvk_read_floats(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest);
cvk_result cvk_read_uints(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest);
/* One of the names name_of gives for 0, 1, ... (NULL past the last); what names the kind of
   value in the message ("unknown linear solver \"foo\" (expected rbgs, ...)"). */
cvk_result cvk_read_enum(cvk_reader* rd, json_t* value, const char* path, const char* what,
                         const char* (*name_of)(int), int* out);
/* "a, b, c or d": the names name_of gives, as cvk_read_enum lists them in its message. */
void cvk_list_names(const char* (*name_of)(int), char* out, size_t size);
/* An object whose every key is in t (or t->shared), read in the order the text has them into
   dest. */
cvk_result cvk_read_object(cvk_reader* rd, const cvk_table* t, json_t* object, const char* path, void* dest);
/* cvk_read_object with f->nested. */
cvk_result cvk_read_nested(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest);

/* A table of the fields in `array`. */
#define FIELDS(array) {.fields = array, .count = sizeof array / sizeof array[0]}

/* ---- readers the scene tables share (lib/scene/scene_json.c, lib/scene/scene_json_time.c) ---- */

/* dest is a cloth: "pins" ([i, j] pairs or vertex indices) and "pin_box" (turns use_pin_box on). */
cvk_result cvk_read_pins(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest);
cvk_result cvk_read_pin_box(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest);
/* dest is a cvk_motion: "keyframes". */
cvk_result cvk_read_keyframes(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest);
/* dest is the scene: "attachments". */
cvk_result cvk_read_attachments(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest);
/* dest is the wind: "wind" turns the air on and reads cvk_wind_table. */
cvk_result cvk_read_wind(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest);
extern const cvk_table cvk_wind_table;
/* dest is the scene: "instances" (count, spacing, offsets) into desc->instances. */
cvk_result cvk_read_instances(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest);
/* The "instances" block (block, read into desc->instances) checked against the scene as
   written and, for more than one copy, expanded: desc then lists every copy's cloths,
   colliders and attachments (lib/scene/scene_instances.c). */
cvk_result cvk_reader_expand_instances(cvk_reader* rd, json_t* block, cvk_scene_desc* desc);
/* The top level of a scene file (lib/scene/scene_json.c). */
extern const cvk_table cvk_scene_table;

/* ---- text ---- */

/* jansson's parse (duplicate keys rejected, any value at the top), except that a bare NaN or
   Infinity becomes a string, so that the number reader reports it with its key path. NULL on
   failure: jerr says why, or *out_of_memory is set. */
json_t* cvk_json_parse(const char* text, size_t size, json_error_t* jerr, bool* out_of_memory);

/* Applies one override "key.path=value" (lib/scene/scene_set.c) to the tree at root, creating what
   the path lacks, and adds the path to rd->set_paths, which must have room for it. */
cvk_result cvk_reader_apply_override(cvk_reader* rd, json_t* root, const char* text);

#endif
