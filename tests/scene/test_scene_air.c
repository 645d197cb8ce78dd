/* The scene keys of the air: "wind" (velocity, gusts), "air_density" and a cloth's "aero":
   defaults, JSON and every message, compared exactly. */
#include "scene_checks.h"

#define CLOTH "'cloths': [{'grid': [4, 3]}]"

static void test_defaults(void)
{
    cvk_scene_desc d = cvk_default_scene_desc();
    CHECK(!d.wind.enabled);
    CHECK_FLOAT(d.wind.velocity[0], 0.0f);
    CHECK_FLOAT(d.wind.gusts.amplitude, 0.0f);
    CHECK_FLOAT(d.wind.gusts.period, 2.0f);
    CHECK_FLOAT(d.wind.gusts.jitter, 0.0f);
    CHECK_FLOAT(d.air_density, 1.2f);
    cvk_cloth_desc c = cvk_default_cloth_desc();
    CHECK_FLOAT(c.aero.drag, 1.0f);
    CHECK_FLOAT(c.aero.lift, 0.2f);
    CHECK_FLOAT(c.aero.friction, 0.02f);
}

static void test_parse(void)
{
    cvk_scene* scene = PARSE_OK("{'cloths': [{'grid': [4, 3], 'aero': {'drag': 1.5, 'lift': 0}}],"
                                " 'wind': {'velocity': [3, 0, 1], 'gusts': {'amplitude': 0.5, 'period': 1,"
                                " 'jitter': 10}}, 'air_density': 1.25}");
    if (!scene)
        return;
    const cvk_scene_desc* d = cvk_scene_get_desc(scene);
    CHECK(d->wind.enabled);
    CHECK_FLOAT(d->wind.velocity[2], 1.0f);
    CHECK_FLOAT(d->wind.gusts.amplitude, 0.5f);
    CHECK_FLOAT(d->wind.gusts.period, 1.0f);
    CHECK_FLOAT(d->wind.gusts.jitter, 10.0f);
    CHECK_FLOAT(d->air_density, 1.25f);
    CHECK_FLOAT(d->cloths[0].aero.drag, 1.5f);
    CHECK_FLOAT(d->cloths[0].aero.lift, 0.0f);
    CHECK_FLOAT(d->cloths[0].aero.friction, 0.02f);
    cvk_scene_destroy(scene);
    scene = PARSE_OK("{" CLOTH ", 'wind': {}}"); /* still air: drag alone */
    if (scene)
        CHECK(cvk_scene_get_desc(scene)->wind.enabled);
    cvk_scene_destroy(scene);
}

static void test_bad(void)
{
    EXPECT_INVALID("{" CLOTH ", 'wind': {'speed': 3}}",
                   "t.json: wind.speed: unknown key (expected one of: velocity, gusts)");
    EXPECT_INVALID("{" CLOTH ", 'wind': {'gusts': {'size': 3}}}",
                   "t.json: wind.gusts.size: unknown key (expected one of: amplitude, period, jitter)");
    EXPECT_INVALID("{" CLOTH ", 'wind': {'velocity': [1, 2]}}",
                   "t.json: wind.velocity: expected an array of 3 numbers, got an array of 2");
    EXPECT_INVALID("{" CLOTH ", 'wind': {'velocity': [800, 0, 0]}}",
                   "t.json: wind.velocity: must be at most 700 m/s fast, got 800 m/s");
    EXPECT_INVALID("{" CLOTH ", 'wind': {'gusts': {'amplitude': 1.5}}}",
                   "t.json: wind.gusts.amplitude: must be at most 1, got 1.5");
    EXPECT_INVALID("{" CLOTH ", 'wind': {'gusts': {'period': 0}}}",
                   "t.json: wind.gusts.period: must be greater than 0, got 0");
    EXPECT_INVALID("{" CLOTH ", 'wind': {'gusts': {'jitter': -5}}}",
                   "t.json: wind.gusts.jitter: must be at least 0, got -5");
    EXPECT_INVALID("{" CLOTH ", 'air_density': 0}", "t.json: air_density: must be greater than 0, got 0");
    EXPECT_INVALID("{'cloths': [{'aero': {'drag': -1}}]}",
                   "t.json: cloths.0.aero.drag: must be at least 0, got -1");
    EXPECT_INVALID("{'cloths': [{'aero': {'lift': 101}}]}",
                   "t.json: cloths.0.aero.lift: must be at most 100, got 101");
    EXPECT_INVALID("{'cloths': [{'aero': {'pressure': 1}}]}",
                   "t.json: cloths.0.aero.pressure: unknown key (expected one of: drag, lift, friction)");
    EXPECT_INVALID("{" CLOTH ", 'solver': {'method': 'implicit', 'linear': 'cg'}, 'wind': {}}",
                   "t.json: solver.method: implicit does not apply wind yet; remove \"wind\", or use pd");
    EXPECT_INVALID("{" CLOTH ", 'solver': {'linear': 'gs-cpu'}, 'wind': {}}",
                   "t.json: solver.linear: gs-cpu (the host reference) does not apply wind; remove "
                   "\"wind\", or use rbgs, jacobi or chebyshev");
}

int main(void)
{
    test_defaults();
    test_parse();
    test_bad();
    printf("%d checks, %d failed\n", T.checks, T.failures);
    return T.failures ? 1 : 0;
}
