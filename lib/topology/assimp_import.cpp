/* Assimp's importer object behind a C interface (assimp_import.h). No exception leaves this
   file: Assimp reports a bad file through its error string, the importer's own allocations may
   throw std::bad_alloc, which becomes "out of host memory", and any other exception becomes its
   text. */
#include "topology/assimp_import.h"

#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <cstdio>
#include <exception>
#include <new>

struct cvk_assimp {
    Assimp::Importer importer;
};

namespace {

/* The scene `step` leaves in a's importer, or nullptr with the reason in why. */
template <typename Step>
const aiScene* guarded(cvk_assimp* a, Step step, char* why, size_t why_size)
{
    const aiScene* scene = nullptr;
    const char* reason = "";
    try {
        scene = step(a->importer);
        if (!scene)
            reason = a->importer.GetErrorString();
    } catch (const std::bad_alloc&) {
        reason = "out of host memory";
    } catch (const std::exception& e) {
        // e is gone after its handler: its text is copied here
        if (why && why_size > 0)
            std::snprintf(why, why_size, "%s", e.what());
        return nullptr;
    } catch (...) {
        reason = "Assimp stopped with an exception of no known type";
    }
    if (!scene && why && why_size > 0)
        std::snprintf(why, why_size, "%s", reason ? reason : "");
    return scene;
}

} // namespace

extern "C" const aiScene* cvk_assimp_read(const char* path, cvk_assimp** importer, char* why,
                                          size_t why_size)
{
    cvk_assimp* a = new (std::nothrow) cvk_assimp;
    const aiScene* scene = nullptr;
    if (a)
        scene = guarded(a, [path](Assimp::Importer& i) { return i.ReadFile(path, 0); }, why,
                        why_size);
    else if (why && why_size > 0)
        std::snprintf(why, why_size, "out of host memory");
    if (!scene) {
        delete a;
        a = nullptr;
    }
    *importer = a;
    return scene;
}

extern "C" const aiScene* cvk_assimp_post_process(cvk_assimp* a, unsigned steps, char* why,
                                                  size_t why_size)
{
    return guarded(a, [steps](Assimp::Importer& i) { return i.ApplyPostProcessing(steps); },
                   why, why_size);
}

extern "C" void cvk_assimp_free(cvk_assimp* a)
{
    delete a;
}
