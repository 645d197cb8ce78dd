/* Assimp's importer object behind a C interface (assimp_import.h). No exception leaves this
   file: Assimp reports a bad file through its error string, and the importer's own allocations
   may throw std::bad_alloc, which becomes "out of host memory". */
#include "topology/assimp_import.h"

#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <cstdio>
#include <new>

struct cvk_assimp {
    Assimp::Importer importer;
    const aiScene* scene = nullptr;
};

namespace {

void say(char* why, size_t why_size, const char* text)
{
    if (why && why_size > 0)
        std::snprintf(why, why_size, "%s", text ? text : "");
}

} // namespace

extern "C" cvk_assimp* cvk_assimp_read(const char* path, char* why, size_t why_size)
{
    cvk_assimp* a = new (std::nothrow) cvk_assimp;
    if (!a) {
        say(why, why_size, "out of host memory");
        return nullptr;
    }
    try {
        a->scene = a->importer.ReadFile(path, 0);
    } catch (const std::bad_alloc&) {
        delete a;
        say(why, why_size, "out of host memory");
        return nullptr;
    } catch (...) {
        delete a;
        say(why, why_size, "");
        return nullptr;
    }
    if (!a->scene) {
        say(why, why_size, a->importer.GetErrorString());
        delete a;
        return nullptr;
    }
    return a;
}

extern "C" const aiScene* cvk_assimp_scene(const cvk_assimp* a)
{
    return a ? a->scene : nullptr;
}

extern "C" bool cvk_assimp_post_process(cvk_assimp* a, unsigned steps, char* why,
                                        size_t why_size)
{
    try {
        a->scene = a->importer.ApplyPostProcessing(steps);
    } catch (const std::bad_alloc&) {
        a->scene = nullptr;
        say(why, why_size, "out of host memory");
        return false;
    } catch (...) {
        a->scene = nullptr;
        say(why, why_size, "");
        return false;
    }
    if (!a->scene)
        say(why, why_size, a->importer.GetErrorString());
    return a->scene != nullptr;
}

extern "C" void cvk_assimp_free(cvk_assimp* a)
{
    delete a;
}
