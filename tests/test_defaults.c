/* Every description a create call reads comes from its cvk_default_*_desc() function: the
   values it returns (what a zeroed description meant before descriptions carried a cookie),
   and the refusal, with its sentence, of a description that skipped it. The scene, cloth and
   collider descriptions are checked in test_scene.c and test_scene_collide.c. */
#include "harness.h"

/* `r` is CVK_ERROR_INVALID_ARGUMENT with exactly `want` as the message. */
static void expect_refused(const char* call, cvk_result r, const cvk_error* err, const char* want)
{
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT, "%s returned %s, not CVK_ERROR_INVALID_ARGUMENT", call,
          cvk_result_name(r));
    CHECK(err->result == r, "%s: the error says %s, the call returned %s", call,
          cvk_result_name(err->result), cvk_result_name(r));
    CHECK(strcmp(err->message, want) == 0, "%s: message \"%s\", want \"%s\"", call, err->message,
          want);
}

/* ---- the context --------------------------------------------------------------------------- */

static void context_defaults(void)
{
    cvk_context_desc d = cvk_default_context_desc();
    CHECK(d.validation == 0, "validation %d, want 0 ($CLOTHVK_VALIDATION decides)", d.validation);
    CHECK(d.device_name == NULL, "device_name \"%s\", want NULL", d.device_name);
    CHECK(d.log == NULL && d.log_user == NULL, "a log callback by default");
    CHECK(d.instance == VK_NULL_HANDLE && d.physical_device == VK_NULL_HANDLE &&
              d.device == VK_NULL_HANDLE && d.queue == VK_NULL_HANDLE && d.queue_family == 0,
          "adoption handles set by default");
    CHECK(d.cookie_ != 0, "no cookie");
}

static void context_refuses_a_description_without_defaults(void)
{
    cvk_error err = {0};
    cvk_context* ctx = (cvk_context*)&err; /* anything but NULL: the call must clear it */
    cvk_context_desc zero = {0};
    cvk_result r = cvk_context_create(&zero, &ctx, &err);
    expect_refused("cvk_context_create", r, &err,
                   "cvk_context_create: the description did not come from "
                   "cvk_default_context_desc()");
    CHECK(ctx == NULL, "a context came back from a refused description");
    r = cvk_context_create(NULL, &ctx, &err);
    expect_refused("cvk_context_create(NULL)", r, &err,
                   "cvk_context_create needs a description and an output pointer");
}

int main(void)
{
    context_defaults();
    context_refuses_a_description_without_defaults();
    cvk_context* ctx = harness_context();
    return harness_finish(ctx);
}
