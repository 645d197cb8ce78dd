/* Colouring any constraint graph: the free vertices of a cloth get colours such that no spring
   joins two of one colour, so the solver can update a whole colour at once. Grids keep their
   closed-form colourings (cvk_grid_colour); everything else comes here. */
#ifndef CVK_COLOUR_H
#define CVK_COLOUR_H

#include "topology/topology.h"

#define CVK_NO_COLOUR UINT32_MAX

/* Colours vertices [0, vertex_count) of the graph whose edges are `springs` (their type is
   ignored). Pinned vertices (pinned[v] != 0; pinned may be NULL) take CVK_NO_COLOUR and
   constrain nothing. Writes colour[v] for every vertex and the number of colours used to
   *colour_count (0 when no vertex is free).

   Greedy first fit in smallest-last order (at most degeneracy + 1 colours, never more than
   the largest degree + 1), then sweeps that move vertices to the smallest colour they are
   allowed so the colour sizes even out without adding a colour. Deterministic: the same
   graph gives the same colours. O(V + E + 32·V) time.

   CVK_ERROR_DEVICE_LIMIT when more than CVK_MAX_COLOURS colours would be needed. */
cvk_result cvk_colour_graph(uint32_t vertex_count, const cvk_topo_spring* springs,
                            uint32_t spring_count, const uint8_t* pinned, uint32_t* colour,
                            uint32_t* colour_count, cvk_error* error);

#endif
