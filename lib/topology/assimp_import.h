/* Assimp's importer object behind a C interface (assimp_import.cpp). Each read has an importer
   of its own, and so an error string of its own: Assimp's C interface (aiImportFile,
   aiGetErrorString) keeps the last error in one process-wide string, which two threads reading
   bad files at once write under each other (test_topology's check_threads). */
#ifndef CVK_ASSIMP_IMPORT_H
#define CVK_ASSIMP_IMPORT_H

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

struct aiScene;
typedef struct cvk_assimp cvk_assimp;

/* Reads the file at path with no post-processing step; NULL where it cannot, with Assimp's
   reason (or "out of host memory") in why. */
cvk_assimp* cvk_assimp_read(const char* path, char* why, size_t why_size);
/* The scene read, or after cvk_assimp_post_process its steps applied; owned by a. */
const struct aiScene* cvk_assimp_scene(const cvk_assimp* a);
/* Applies Assimp's post-processing steps (aiProcess_* flags) to a's scene; false with the reason
   in why where a step fails (a's scene is gone then). */
bool cvk_assimp_post_process(cvk_assimp* a, unsigned steps, char* why, size_t why_size);
/* Frees the importer and its scene; NULL is allowed. */
void cvk_assimp_free(cvk_assimp* a);

#ifdef __cplusplus
}
#endif

#endif
