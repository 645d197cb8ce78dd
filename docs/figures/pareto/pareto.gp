# Draws pareto.png from pareto.csv (clothvk-bench). Run in this folder: gnuplot pareto.gp
if (!exists("out")) out = "pareto.png"
set terminal pngcairo noenhanced size 1400,550 font "sans,10"
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
$front_residual << EOD
0.702868,0.0517986,2x1
0.910892,0.0452488,2x1
1.25061,0.0394161,2x2
1.38687,0.0301721,4x1
1.6529,0.0204715,2x2
2.49662,0.0138687,2x4
4.64227,0.00901506,2x8
4.87946,0.00725166,4x4
8.76356,0.00385937,4x8
13.5917,0.00233712,2x32
17.4396,0.00178693,4x16
18.5069,0.00138787,8x8
26.9792,0.000599472,4x32
36.3728,0.000559116,8x16
56.0963,0.000139629,8x32
EOD
$front_trajectory << EOD
0.702868,0.151723,2x1
0.910892,0.147944,2x1
1.6529,0.145568,2x2
2.49662,0.142094,2x4
2.73365,0.136561,4x2
4.87946,0.130342,4x4
8.76356,0.123118,4x8
9.70857,0.110523,8x4
18.5069,0.102202,8x8
36.3728,0.0962049,8x16
56.0963,0.0887823,8x32
EOD
set multiplot layout 1,2 title "hanging.json: error after 0.256 s against GPU time per frame (gs-cpu: host), on llvmpipe (LLVM 15.0.6, 256 bits), LP_NUM_THREADS=0"
set xlabel "time per frame (ms)"
set format y "%.0e"
set key bottom left
set title "residual (m²); front labelled substeps x iterations; unstable settings left out"
set ylabel "residual (m²)"
set logscale x
set logscale y
plot "pareto.csv" using "frame_ms":(strcol("label") eq "jacobi" && column("stable") == 1 ? column("residual") : NaN) with points linestyle 1 title "jacobi", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "chebyshev" && column("stable") == 1 ? column("residual") : NaN) with points linestyle 2 title "chebyshev", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "rbgs" && column("stable") == 1 ? column("residual") : NaN) with points linestyle 3 title "rbgs", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "rbgs:1.7" && column("stable") == 1 ? column("residual") : NaN) with points linestyle 4 title "rbgs ω=1.7", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "gs-cpu" && column("stable") == 1 ? column("residual") : NaN) with points linestyle 5 dashtype 2 title "gs-cpu", \
     $front_residual using 1:2 with lines linecolor rgb "black" title "Pareto front", \
     $front_residual using 1:2:3 with labels left offset 0.5,0.3 font ",7" notitle, \
     6.65628562e-09 with lines linecolor rgb "black" dashtype 3 title "reference (converged, h/4)"
set title "trajectory error (m RMS); front labelled substeps x iterations; unstable settings left out"
set ylabel "trajectory error (m RMS)"
set logscale x
set logscale y
plot "pareto.csv" using "frame_ms":(strcol("label") eq "jacobi" && column("stable") == 1 ? column("trajectory_error") : NaN) with points linestyle 1 title "jacobi", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "chebyshev" && column("stable") == 1 ? column("trajectory_error") : NaN) with points linestyle 2 title "chebyshev", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "rbgs" && column("stable") == 1 ? column("trajectory_error") : NaN) with points linestyle 3 title "rbgs", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "rbgs:1.7" && column("stable") == 1 ? column("trajectory_error") : NaN) with points linestyle 4 title "rbgs ω=1.7", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "gs-cpu" && column("stable") == 1 ? column("trajectory_error") : NaN) with points linestyle 5 dashtype 2 title "gs-cpu", \
     $front_trajectory using 1:2 with lines linecolor rgb "black" title "Pareto front", \
     $front_trajectory using 1:2:3 with labels left offset 0.5,0.3 font ",7" notitle
unset multiplot
