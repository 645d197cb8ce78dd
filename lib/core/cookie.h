/* The tags the cvk_default_*_desc() functions put in a description's cookie_, one list for
   every description. The call that reads a description refuses one whose cookie differs: it
   skipped its defaults function, so the fields its caller did not set are zero instead of the
   defaults. Arbitrary (four letters of the name) and never zero, so a zero-initialised
   description is caught. */
#ifndef CVK_COOKIE_H
#define CVK_COOKIE_H

#define CVK_COOKIE_SCENE 0x53634e65u      /* "ScNe" */
#define CVK_COOKIE_CLOTH 0x436c5468u      /* "ClTh" */
#define CVK_COOKIE_COLLIDER 0x436f4c64u   /* "CoLd" */
#define CVK_COOKIE_ATTACHMENT 0x41744368u /* "AtCh" */
#define CVK_COOKIE_CONTEXT 0x43745874u    /* "CtXt" */
#define CVK_COOKIE_SIM 0x53694d75u        /* "SiMu" */
#define CVK_COOKIE_MESH 0x4d655368u       /* "MeSh" */
#define CVK_COOKIE_RENDER 0x52654e64u     /* "ReNd" */

#endif
