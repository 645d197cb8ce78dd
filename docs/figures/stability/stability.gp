# Draws stability.png from stability.csv (clothvk-bench). Run in this folder: gnuplot stability.gp
if (!exists("out")) out = "stability.png"
set terminal pngcairo noenhanced size 1500,390 font "sans,10"
set output out
set datafile separator ","
set grid
set multiplot layout 1,4 title "hanging.json: stable region over h and stiffness (0.5 s simulated, at least 50 steps), on llvmpipe (LLVM 15.0.6, 256 bits), LP_NUM_THREADS=0"
set logscale xy
set format x "%.0e"
set format y "%.0e"
set xlabel "h (s)"
set ylabel "stiffness (N/m)"
set offsets graph 0.05, graph 0.05, graph 0.05, graph 0.45
set key bottom center horizontal maxcols 3 font ",8"
set title "jacobi 4x4, damping 0"
plot "stability.csv" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "jacobi" && column("iterations") == 16 && column("damping") == 0 && column("stable") == 1 ? column("stiffness") : NaN) with points pointtype 7 linecolor rgb "#2ca02c" title "stable", \
     "" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "jacobi" && column("iterations") == 16 && column("damping") == 0 && strcol("reason") eq "nan" ? column("stiffness") : NaN) with points pointtype 2 linecolor rgb "#d62728" title "NaN", \
     "" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "jacobi" && column("iterations") == 16 && column("damping") == 0 && strcol("reason") eq "energy" ? column("stiffness") : NaN) with points pointtype 9 linecolor rgb "#ff7f0e" title "energy", \
     "" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "jacobi" && column("iterations") == 16 && column("damping") == 0 && strcol("reason") eq "stretch" ? column("stiffness") : NaN) with points pointtype 5 linecolor rgb "#9467bd" title "stretch", \
     "" using "dt":(strcol("kind") eq "limit" && strcol("label") eq "jacobi" && column("iterations") == 16 && column("damping") == 0 ? column("stiffness") : NaN) with linespoints linecolor rgb "black" pointtype 1 title "largest stable h"
set title "chebyshev 4x4, damping 0"
plot "stability.csv" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "chebyshev" && column("iterations") == 16 && column("damping") == 0 && column("stable") == 1 ? column("stiffness") : NaN) with points pointtype 7 linecolor rgb "#2ca02c" title "stable", \
     "" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "chebyshev" && column("iterations") == 16 && column("damping") == 0 && strcol("reason") eq "nan" ? column("stiffness") : NaN) with points pointtype 2 linecolor rgb "#d62728" title "NaN", \
     "" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "chebyshev" && column("iterations") == 16 && column("damping") == 0 && strcol("reason") eq "energy" ? column("stiffness") : NaN) with points pointtype 9 linecolor rgb "#ff7f0e" title "energy", \
     "" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "chebyshev" && column("iterations") == 16 && column("damping") == 0 && strcol("reason") eq "stretch" ? column("stiffness") : NaN) with points pointtype 5 linecolor rgb "#9467bd" title "stretch", \
     "" using "dt":(strcol("kind") eq "limit" && strcol("label") eq "chebyshev" && column("iterations") == 16 && column("damping") == 0 ? column("stiffness") : NaN) with linespoints linecolor rgb "black" pointtype 1 title "largest stable h"
set title "rbgs 4x4, damping 0"
plot "stability.csv" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "rbgs" && column("iterations") == 16 && column("damping") == 0 && column("stable") == 1 ? column("stiffness") : NaN) with points pointtype 7 linecolor rgb "#2ca02c" title "stable", \
     "" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "rbgs" && column("iterations") == 16 && column("damping") == 0 && strcol("reason") eq "nan" ? column("stiffness") : NaN) with points pointtype 2 linecolor rgb "#d62728" title "NaN", \
     "" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "rbgs" && column("iterations") == 16 && column("damping") == 0 && strcol("reason") eq "energy" ? column("stiffness") : NaN) with points pointtype 9 linecolor rgb "#ff7f0e" title "energy", \
     "" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "rbgs" && column("iterations") == 16 && column("damping") == 0 && strcol("reason") eq "stretch" ? column("stiffness") : NaN) with points pointtype 5 linecolor rgb "#9467bd" title "stretch", \
     "" using "dt":(strcol("kind") eq "limit" && strcol("label") eq "rbgs" && column("iterations") == 16 && column("damping") == 0 ? column("stiffness") : NaN) with linespoints linecolor rgb "black" pointtype 1 title "largest stable h"
set title "rbgs:1.7 4x4, damping 0"
plot "stability.csv" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "rbgs:1.7" && column("iterations") == 16 && column("damping") == 0 && column("stable") == 1 ? column("stiffness") : NaN) with points pointtype 7 linecolor rgb "#2ca02c" title "stable", \
     "" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "rbgs:1.7" && column("iterations") == 16 && column("damping") == 0 && strcol("reason") eq "nan" ? column("stiffness") : NaN) with points pointtype 2 linecolor rgb "#d62728" title "NaN", \
     "" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "rbgs:1.7" && column("iterations") == 16 && column("damping") == 0 && strcol("reason") eq "energy" ? column("stiffness") : NaN) with points pointtype 9 linecolor rgb "#ff7f0e" title "energy", \
     "" using "dt":(strcol("kind") eq "grid" && strcol("label") eq "rbgs:1.7" && column("iterations") == 16 && column("damping") == 0 && strcol("reason") eq "stretch" ? column("stiffness") : NaN) with points pointtype 5 linecolor rgb "#9467bd" title "stretch", \
     "" using "dt":(strcol("kind") eq "limit" && strcol("label") eq "rbgs:1.7" && column("iterations") == 16 && column("damping") == 0 ? column("stiffness") : NaN) with linespoints linecolor rgb "black" pointtype 1 title "largest stable h"
unset multiplot
