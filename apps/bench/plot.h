/* Plots drawn by gnuplot as a separate process. */
#ifndef CVK_BENCH_PLOT_H
#define CVK_BENCH_PLOT_H

#include "bench.h"

/* Writes dir/NAME.gp (a common preamble, then `body`, which plots NAME.csv) and runs gnuplot
   on it in dir, which writes dir/NAME.png (through a temporary name: complete or absent).
   $CLOTHVK_GNUPLOT names another gnuplot. Returns false with one sentence in `message` when
   the script could not be written or gnuplot is missing or failed. */
bool bench_plot(const char* dir, const char* name, int width, int height, const bench_text* body,
                char* message, size_t message_size);

/* Plots column y against column x, one series per --solvers entry (rows whose "label" is the
   entry's and, when `only` is not NULL, whose column `only` is 1), skipping series the axes
   cannot show, then the plot clauses in `extra` (may be NULL; "a, b" without a leading
   comma). A "no data" panel when no series of ours is left. */
void bench_plot_solvers(bench* b, const char* csv, const char* x, const char* y, const char* with,
                        bool log_x, bool log_y, const char* only, const bench_text* extra);
/* An empty panel that says "no data". */
void bench_plot_empty(bench_text* t);
/* Line styles 1.. in fixed colours, so a solver has one colour in every panel. */
void bench_plot_styles(bench_text* t);

#endif
