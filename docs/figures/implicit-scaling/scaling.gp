# Draws scaling.png from scaling.csv (clothvk-bench). Run in this folder: gnuplot scaling.gp
if (!exists("out")) out = "scaling.png"
set terminal pngcairo noenhanced size 1200,550 font "sans,10"
set output out
set datafile separator ","
set grid
set style line 1 linecolor rgb "#1f77b4" pointtype 1 linewidth 1.5
set style line 2 linecolor rgb "#d62728" pointtype 2 linewidth 1.5
set style line 3 linecolor rgb "#2ca02c" pointtype 3 linewidth 1.5
set style line 4 linecolor rgb "#ff7f0e" pointtype 4 linewidth 1.5
set style line 5 linecolor rgb "#9467bd" pointtype 5 linewidth 1.5
set style line 6 linecolor rgb "#8c564b" pointtype 6 linewidth 1.5
set style line 7 linecolor rgb "#e377c2" pointtype 7 linewidth 1.5
set style line 8 linecolor rgb "#7f7f7f" pointtype 8 linewidth 1.5
set style line 9 linecolor rgb "#1f77b4" pointtype 9 linewidth 1.5
set style line 10 linecolor rgb "#d62728" pointtype 10 linewidth 1.5
set style line 11 linecolor rgb "#2ca02c" pointtype 11 linewidth 1.5
set style line 12 linecolor rgb "#ff7f0e" pointtype 12 linewidth 1.5
set style line 13 linecolor rgb "#9467bd" pointtype 13 linewidth 1.5
set style line 14 linecolor rgb "#8c564b" pointtype 1 linewidth 1.5
set style line 15 linecolor rgb "#e377c2" pointtype 2 linewidth 1.5
set style line 16 linecolor rgb "#7f7f7f" pointtype 3 linewidth 1.5
set style line 17 linecolor rgb "#1f77b4" pointtype 4 linewidth 1.5
set style line 18 linecolor rgb "#d62728" pointtype 5 linewidth 1.5
set style line 19 linecolor rgb "#2ca02c" pointtype 6 linewidth 1.5
set style line 20 linecolor rgb "#ff7f0e" pointtype 7 linewidth 1.5
set style line 21 linecolor rgb "#9467bd" pointtype 8 linewidth 1.5
set style line 22 linecolor rgb "#8c564b" pointtype 9 linewidth 1.5
set style line 23 linecolor rgb "#e377c2" pointtype 10 linewidth 1.5
set style line 24 linecolor rgb "#7f7f7f" pointtype 11 linewidth 1.5
set style line 25 linecolor rgb "#1f77b4" pointtype 12 linewidth 1.5
set style line 26 linecolor rgb "#d62728" pointtype 13 linewidth 1.5
set style line 27 linecolor rgb "#2ca02c" pointtype 1 linewidth 1.5
set style line 28 linecolor rgb "#ff7f0e" pointtype 2 linewidth 1.5
set style line 29 linecolor rgb "#9467bd" pointtype 3 linewidth 1.5
set style line 30 linecolor rgb "#8c564b" pointtype 4 linewidth 1.5
set style line 31 linecolor rgb "#e377c2" pointtype 5 linewidth 1.5
set style line 32 linecolor rgb "#7f7f7f" pointtype 6 linewidth 1.5
set multiplot layout 1,2 title "scaling, 1 substeps per frame, on llvmpipe (LLVM 15.0.6, 256 bits), LP_NUM_THREADS=0"
set logscale xy
set xlabel "particles"
set format x "%.0e"
set key top left font ",8"
set title "GPU time per frame"
set ylabel "ms per frame"
plot "scaling.csv" using "particles":(strcol("label") eq "cg" && column("iterations") == 10 ? column("frame_ms") : NaN) with linespoints linestyle 1 dashtype 1 title "implicit cg, 10 sweeps", \
     "scaling.csv" using "particles":(strcol("label") eq "cg" && column("iterations") == 30 ? column("frame_ms") : NaN) with linespoints linestyle 1 dashtype 2 title "implicit cg, 30 sweeps", \
     "scaling.csv" using "particles":(strcol("label") eq "cg" && column("iterations") == 50 ? column("frame_ms") : NaN) with linespoints linestyle 1 dashtype 3 title "implicit cg, 50 sweeps", \
     "scaling.csv" using "particles":(strcol("label") eq "cg" && column("iterations") == 70 ? column("frame_ms") : NaN) with linespoints linestyle 1 dashtype 4 title "implicit cg, 70 sweeps", \
     "scaling.csv" using "particles":(strcol("label") eq "implicit-jacobi" && column("iterations") == 10 ? column("frame_ms") : NaN) with linespoints linestyle 2 dashtype 1 title "implicit jacobi, 10 sweeps", \
     "scaling.csv" using "particles":(strcol("label") eq "implicit-jacobi" && column("iterations") == 30 ? column("frame_ms") : NaN) with linespoints linestyle 2 dashtype 2 title "implicit jacobi, 30 sweeps", \
     "scaling.csv" using "particles":(strcol("label") eq "implicit-jacobi" && column("iterations") == 50 ? column("frame_ms") : NaN) with linespoints linestyle 2 dashtype 3 title "implicit jacobi, 50 sweeps", \
     "scaling.csv" using "particles":(strcol("label") eq "implicit-jacobi" && column("iterations") == 70 ? column("frame_ms") : NaN) with linespoints linestyle 2 dashtype 4 title "implicit jacobi, 70 sweeps"
set title "solve time per particle and sweep"
set ylabel "ns"
plot "scaling.csv" using "particles":(strcol("label") eq "cg" && column("iterations") == 10 ? column("ns_per_particle_iteration") : NaN) with linespoints linestyle 1 dashtype 1 title "implicit cg, 10 sweeps", \
     "scaling.csv" using "particles":(strcol("label") eq "cg" && column("iterations") == 30 ? column("ns_per_particle_iteration") : NaN) with linespoints linestyle 1 dashtype 2 title "implicit cg, 30 sweeps", \
     "scaling.csv" using "particles":(strcol("label") eq "cg" && column("iterations") == 50 ? column("ns_per_particle_iteration") : NaN) with linespoints linestyle 1 dashtype 3 title "implicit cg, 50 sweeps", \
     "scaling.csv" using "particles":(strcol("label") eq "cg" && column("iterations") == 70 ? column("ns_per_particle_iteration") : NaN) with linespoints linestyle 1 dashtype 4 title "implicit cg, 70 sweeps", \
     "scaling.csv" using "particles":(strcol("label") eq "implicit-jacobi" && column("iterations") == 10 ? column("ns_per_particle_iteration") : NaN) with linespoints linestyle 2 dashtype 1 title "implicit jacobi, 10 sweeps", \
     "scaling.csv" using "particles":(strcol("label") eq "implicit-jacobi" && column("iterations") == 30 ? column("ns_per_particle_iteration") : NaN) with linespoints linestyle 2 dashtype 2 title "implicit jacobi, 30 sweeps", \
     "scaling.csv" using "particles":(strcol("label") eq "implicit-jacobi" && column("iterations") == 50 ? column("ns_per_particle_iteration") : NaN) with linespoints linestyle 2 dashtype 3 title "implicit jacobi, 50 sweeps", \
     "scaling.csv" using "particles":(strcol("label") eq "implicit-jacobi" && column("iterations") == 70 ? column("ns_per_particle_iteration") : NaN) with linespoints linestyle 2 dashtype 4 title "implicit jacobi, 70 sweeps"
unset multiplot
