// The constants of a rendered frame, shared by every pass: the Frame block (set 0, binding 0,
// std140), declared with its C side (cvk_frame_uniforms) in shared/frame.h.
#include "shared/frame.h"
