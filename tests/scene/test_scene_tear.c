/* The scene key of tearing: a cloth's "tearing" block, its default, JSON, --set and every
   message, compared exactly; every solver takes it, tethers do not. */
#include "scene_checks.h"

#define CLOTH "'cloths': [{'grid': [4, 3]}]"
#define TEARING_CLOTH "'cloths': [{'grid': [4, 3], 'tearing': {'max_stretch': 0.5}}]"

static void test_defaults(void)
{
    cvk_cloth_desc c = cvk_default_cloth_desc();
    CHECK_FLOAT(c.tearing.max_stretch, 0.0f);
}

static void test_parse(void)
{
    cvk_scene* scene = PARSE_OK("{'cloths': [{'grid': [4, 3], 'tearing': {'max_stretch': 0.5}},"
                                " {'grid': [2, 2]}]}");
    if (scene) {
        const cvk_scene_desc* d = cvk_scene_get_desc(scene);
        CHECK_FLOAT(d->cloths[0].tearing.max_stretch, 0.5f);
        CHECK_FLOAT(d->cloths[1].tearing.max_stretch, 0.0f);
    }
    cvk_scene_destroy(scene);
    scene = PARSE_OK("{'cloths': [{'grid': [4, 3], 'tearing': {}}]}"); /* an empty block: off */
    if (scene)
        CHECK_FLOAT(cvk_scene_get_desc(scene)->cloths[0].tearing.max_stretch, 0.0f);
    cvk_scene_destroy(scene);
    const char* sets[] = {"cloths.0.tearing.max_stretch=0.25"};
    scene = PARSE_OK_SET("{" CLOTH "}", sets);
    if (scene)
        CHECK_FLOAT(cvk_scene_get_desc(scene)->cloths[0].tearing.max_stretch, 0.25f);
    cvk_scene_destroy(scene);
    /* every solver tears */
    scene = PARSE_OK("{" TEARING_CLOTH ", 'solver': {'linear': 'gs-cpu'}}");
    cvk_scene_destroy(scene);
    scene = PARSE_OK("{" TEARING_CLOTH ", 'solver': {'method': 'implicit', 'linear': 'cg'}}");
    cvk_scene_destroy(scene);
    scene = PARSE_OK("{" TEARING_CLOTH ", 'solver': {'method': 'explicit'}}");
    cvk_scene_destroy(scene);
    /* 0 with tethers, or with a solver that does not tear, is no tearing: allowed */
    scene = PARSE_OK("{'solver': {'linear': 'gs-cpu'}, 'cloths': [{'grid': [4, 3], 'pins': [[0, 0]],"
                     " 'tethers': 1, 'tearing': {'max_stretch': 0}}]}");
    cvk_scene_destroy(scene);
}

static void test_bad(void)
{
    EXPECT_INVALID("{'cloths': [{'tearing': 0.5}]}",
                   "t.json: cloths.0.tearing: expected an object, got the number 0.5");
    EXPECT_INVALID("{'cloths': [{'tearing': {'threshold': 3}}]}",
                   "t.json: cloths.0.tearing.threshold: unknown key (expected one of: max_stretch)");
    EXPECT_INVALID("{'cloths': [{'tearing': {'max_stretch': '0.5'}}]}",
                   "t.json: cloths.0.tearing.max_stretch: expected a number, got the string \"0.5\"");
    EXPECT_INVALID("{'cloths': [{}, {'tearing': {'max_stretch': -0.1}}]}",
                   "t.json: cloths.1.tearing.max_stretch: must be at least 0, got -0.1");
    EXPECT_INVALID("{'cloths': [{'tearing': {'max_stretch': 12}}]}",
                   "t.json: cloths.0.tearing.max_stretch: must be at most 9 (a spring 10 times its "
                   "rest length is a diverged solve), got 12");
    EXPECT_INVALID("{'cloths': [{'pins': [[0, 0]], 'tethers': 1, 'tearing': {'max_stretch': 0.5}}]}",
                   "t.json: cloths.0.tearing: a cloth with tethers cannot tear (a tether would pull "
                   "a torn-off piece back towards its pins); remove \"tethers\" or \"tearing\"");
    EXPECT_SET_ERROR("{" CLOTH "}", "cloths.0.tearing.max_stretch=-1",
                     "t.json: cloths.0.tearing.max_stretch (from --set): must be at least 0, got -1");
}

int main(void)
{
    test_defaults();
    test_parse();
    test_bad();
    printf("%d checks, %d failed\n", T.checks, T.failures);
    return T.failures ? 1 : 0;
}
