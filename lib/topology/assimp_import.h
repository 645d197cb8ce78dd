/* Assimp's importer object behind a C interface (assimp_import.cpp). Each read has an importer
   of its own, and so an error string of its own: Assimp's C interface (aiImportFile,
   aiGetErrorString) keeps the last error in one process-wide string, which two threads reading
   bad files at once write under each other (test_topology's check_threads). */
#ifndef CVK_ASSIMP_IMPORT_H
#define CVK_ASSIMP_IMPORT_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

struct aiScene;
typedef struct cvk_assimp cvk_assimp;

/* Reads the file at path with no post-processing step: the scene, owned by *importer, which the
   caller frees; NULL where it cannot (*importer NULL), with Assimp's reason (or "out of host
   memory") in why. */
const struct aiScene* cvk_assimp_read(const char* path, cvk_assimp** importer, char* why,
                                      size_t why_size);
/* Applies Assimp's post-processing steps (aiProcess_* flags) to a's scene: the scene after them,
   or NULL with the reason in why (a's scene is gone then). */
const struct aiScene* cvk_assimp_post_process(cvk_assimp* a, unsigned steps, char* why,
                                              size_t why_size);
/* Frees the importer and its scene; NULL is allowed. */
void cvk_assimp_free(cvk_assimp* a);

#ifdef __cplusplus
}
#endif

#endif
