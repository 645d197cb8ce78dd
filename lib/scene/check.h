/* The checks every part of the scene check shares: key paths, the issue they fill, number and
   array checks, a cloth's pins and pin_box, keyframed motion. Each check returns true when the
   value is fine, else fills the issue ("path: problem") and returns false. */
#ifndef CVK_SCENE_CHECK_H
#define CVK_SCENE_CHECK_H

#include "clothvk.h"

#define CVK_KEY_PATH_MAX 256

/* One thing wrong with a description. path is the dotted key path ("cloths.0.mass",
   "gravity.1"), empty for the scene as a whole; problem is the sentence after "path: ". */
typedef struct cvk_scene_issue {
    char path[CVK_KEY_PATH_MAX];
    char problem[384];
} cvk_scene_issue;

#define CVK_MAX_KEYFRAMES 10000u

/* Largest position coordinate and length, m (a mesh's vertices after its transform too): at
   1e5 m single precision resolves 2^-7 m, about 8 mm, as coarse as a cloth's contact thickness;
   further out contact and springs are rounding noise, and lengths past 1e19 m overflow when
   squared (a sphere of radius 1e38 made NaN of its cloth). */
#define CVK_MAX_COORDINATE 1e5

/* A number as text with as few significant digits as tell it apart from its neighbours, 6 at
   least (as %g): two floats (or doubles) that differ never print alike, so a message shows why
   a value was refused (0.1f is "0.1", 1.00000012f is "1.00000012"). */
typedef struct cvk_number_text {
    char text[32];
} cvk_number_text;
cvk_number_text cvk_float_text(double v);  /* a float's value */
cvk_number_text cvk_double_text(double v); /* a double's (a number of JSON text) */

/* Formats a key path ("cloths.0.mass") into out, cutting what does not fit: keys that users
   write may be longer than any path clothvk makes itself. */
void cvk_key_path(char out[CVK_KEY_PATH_MAX], const char* format, ...) __attribute__((format(printf, 2, 3)));
/* out = "base.key" and "base.index"; returns out. */
const char* cvk_key_join(char out[CVK_KEY_PATH_MAX], const char* base, const char* key);
const char* cvk_key_join_index(char out[CVK_KEY_PATH_MAX], const char* base, uint32_t index);

/* Fills issue with "path: problem" and returns false (for the checks below and their files). */
bool cvk_issue_at(cvk_scene_issue* issue, const char* path, const char* format, ...)
    __attribute__((format(printf, 3, 4)));
/* Parts of the scene check that other descriptions reuse: a cloth's pins and pin_box (against
   the cloth's grid or mesh form) and a keyframed motion; paths start with base. */
bool cvk_check_pins(const cvk_cloth_desc* cloth, const char* base, cvk_scene_issue* issue);
bool cvk_check_pin_box(const cvk_cloth_desc* cloth, const char* base, cvk_scene_issue* issue);
bool cvk_check_motion(const cvk_motion* motion, const char* base, cvk_scene_issue* issue);

/* Finite; low < v; low <= v (the three checks of numbers every block uses). */
bool cvk_check_finite(cvk_scene_issue* issue, const char* path, double v);
bool cvk_check_finite_array(cvk_scene_issue* issue, const char* path, const float* v, uint32_t n);
bool cvk_check_greater(cvk_scene_issue* issue, const char* path, double v, double low);
bool cvk_check_at_least(cvk_scene_issue* issue, const char* path, double v, double low);
/* Positions: each of n coordinates finite and at most CVK_MAX_COORDINATE in magnitude; a length
   (a radius, a half extent): greater than 0 and at most CVK_MAX_COORDINATE; a mesh's scale
   factor: finite and not 0. */
bool cvk_check_position(cvk_scene_issue* issue, const char* path, const float* v, uint32_t n);
bool cvk_check_length(cvk_scene_issue* issue, const char* path, double v);
bool cvk_check_scale(cvk_scene_issue* issue, const char* path, double v);
/* Counts: low <= v, and low <= v <= high. */
bool cvk_check_count(cvk_scene_issue* issue, const char* path, uint32_t v, uint32_t low);
bool cvk_check_count_range(cvk_scene_issue* issue, const char* path, uint32_t v, uint32_t low,
                           uint32_t high);
/* low <= v < high; low < v < high; low <= v <= high; low <= v[i] <= high for each of n
   elements. */
bool cvk_check_half_open(cvk_scene_issue* issue, const char* path, double v, double low,
                         double high);
bool cvk_check_open(cvk_scene_issue* issue, const char* path, double v, double low, double high);
bool cvk_check_closed(cvk_scene_issue* issue, const char* path, double v, double low, double high);
bool cvk_check_closed_array(cvk_scene_issue* issue, const char* path, const float* v, uint32_t n,
                            double low, double high);
/* A rotation quaternion (x, y, z, w): finite and of unit length within a tolerance. */
bool cvk_check_quaternion(cvk_scene_issue* issue, const char* path, const float q[4]);

#endif
