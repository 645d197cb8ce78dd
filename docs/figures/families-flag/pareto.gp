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
0.117777,0.122586,2x1
0.162104,0.0131291,2x1
0.286901,0.00338902,2x2
0.325959,0.00109267,4x1
0.538448,0.000725398,2x4
0.580581,0.000309555,4x2
0.665139,0.000273296,8x1
1.05747,0.000231035,2x8
1.08551,9.74892e-05,4x4
1.1805,5.97476e-05,8x2
2.13164,3.66725e-05,4x8
2.25122,1.75126e-05,8x4
4.21259,1.16744e-05,4x16
4.54443,6.66715e-06,8x8
9.1639,2.77417e-06,8x16
9.71099,1.40612e-07,2x0.01
37.1862,1.29379e-08,4x0.01
64.784,2.3064e-09,8x0.001
75.3502,2.21887e-09,8x0.01
EOD
$front_trajectory << EOD
0.117777,0.107069,2x1
0.162104,0.0490247,2x1
0.286901,0.0254783,2x2
0.325959,0.0136223,4x1
0.538448,0.0120797,2x4
0.580581,0.0106305,4x2
1.05747,0.00851605,2x8
1.56603,0.00844988,8x4
5.69718,0.00755632,8x16
5.78477,0.00752805,4x32
64.784,0.00582359,8x0.001
118.894,0.00299642,1000x1
EOD
set multiplot layout 1,2 title "flag.json: error after 0.256 s against GPU time per frame (gs-cpu: host), on llvmpipe (LLVM 15.0.6, 256 bits), LP_NUM_THREADS=0"
set xlabel "time per frame (ms)"
set datafile missing "nan"
set format y "%.0e"
set key bottom left
set title "residual (m²); front: substeps x iterations (implicit: x tolerance); unstable left out"
set ylabel "residual (m²)"
set logscale x
set logscale y
plot "pareto.csv" using "frame_ms":(strcol("label") eq "rbgs" && column("stable") == 1 ? column("residual") : NaN) with points linestyle 1 title "rbgs", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "rbgs:1.7" && column("stable") == 1 ? column("residual") : NaN) with points linestyle 2 title "rbgs ω=1.7", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "jacobi" && column("stable") == 1 ? column("residual") : NaN) with points linestyle 3 title "jacobi", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "chebyshev" && column("stable") == 1 ? column("residual") : NaN) with points linestyle 4 title "chebyshev", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "cg" && column("stable") == 1 ? column("residual") : NaN) with points linestyle 5 title "implicit cg", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "implicit-jacobi" && column("stable") == 1 ? column("residual") : NaN) with points linestyle 6 title "implicit jacobi", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "verlet" && column("stable") == 1 ? column("residual") : NaN) with points linestyle 7 title "explicit verlet", \
     $front_residual using 1:2 with lines linecolor rgb "black" title "Pareto front", \
     $front_residual using 1:2:3 with labels left offset 0.5,0.3 font ",7" notitle, \
     9.32303871e-09 with lines linecolor rgb "black" dashtype 3 title "reference (converged, h/4)"
set title "trajectory error (m RMS); front: substeps x iterations (implicit: x tolerance); unstable left out"
set ylabel "trajectory error (m RMS)"
set logscale x
set logscale y
plot "pareto.csv" using "frame_ms":(strcol("label") eq "rbgs" && column("stable") == 1 ? column("trajectory_error") : NaN) with points linestyle 1 title "rbgs", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "rbgs:1.7" && column("stable") == 1 ? column("trajectory_error") : NaN) with points linestyle 2 title "rbgs ω=1.7", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "jacobi" && column("stable") == 1 ? column("trajectory_error") : NaN) with points linestyle 3 title "jacobi", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "chebyshev" && column("stable") == 1 ? column("trajectory_error") : NaN) with points linestyle 4 title "chebyshev", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "cg" && column("stable") == 1 ? column("trajectory_error") : NaN) with points linestyle 5 title "implicit cg", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "implicit-jacobi" && column("stable") == 1 ? column("trajectory_error") : NaN) with points linestyle 6 title "implicit jacobi", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "verlet" && column("stable") == 1 ? column("trajectory_error") : NaN) with points linestyle 7 title "explicit verlet", \
     $front_trajectory using 1:2 with lines linecolor rgb "black" title "Pareto front", \
     $front_trajectory using 1:2:3 with labels left offset 0.5,0.3 font ",7" notitle
unset multiplot
