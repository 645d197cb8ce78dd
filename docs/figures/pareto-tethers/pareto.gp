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
1.61806,0.0516839,2x2
1.75169,0.0279202,2x2
3.17016,0.0169135,2x4
5.97335,0.00995581,2x8
6.26127,0.00508844,4x4
11.7159,0.00248927,2x16
12.2347,0.0013623,4x8
22.2082,0.000346568,4x16
44.8129,3.87318e-05,8x16
EOD
$front_trajectory << EOD
1.61806,0.0667201,2x2
1.75169,0.055196,2x2
3.17016,0.0464681,2x4
3.56314,0.0343097,4x2
6.26127,0.019364,4x4
12.2347,0.0137266,4x8
22.2082,0.0116398,4x16
EOD
set multiplot layout 1,2 title "hanging.json: error after 0.256 s against GPU time per frame (gs-cpu: host), on llvmpipe (LLVM 15.0.6, 256 bits), LP_NUM_THREADS=0"
set xlabel "time per frame (ms)"
set datafile missing "nan"
set format y "%.0e"
set key bottom left
set title "residual (m²); front: substeps x iterations (implicit: x tolerance); unstable left out"
set ylabel "residual (m²)"
set logscale x
set logscale y
plot "pareto.csv" using "frame_ms":(strcol("label") eq "rbgs:1.7" && column("stable") == 1 ? column("residual") : NaN) with points linestyle 1 title "rbgs ω=1.7", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "chebyshev" && column("stable") == 1 ? column("residual") : NaN) with points linestyle 2 title "chebyshev", \
     $front_residual using 1:2 with lines linecolor rgb "black" title "Pareto front", \
     $front_residual using 1:2:3 with labels left offset 0.5,0.3 font ",7" notitle, \
     6.65628562e-09 with lines linecolor rgb "black" dashtype 3 title "reference (converged, h/4)"
set title "trajectory error (m RMS); front: substeps x iterations (implicit: x tolerance); unstable left out"
set ylabel "trajectory error (m RMS)"
set logscale x
set logscale y
plot "pareto.csv" using "frame_ms":(strcol("label") eq "rbgs:1.7" && column("stable") == 1 ? column("trajectory_error") : NaN) with points linestyle 1 title "rbgs ω=1.7", \
     "pareto.csv" using "frame_ms":(strcol("label") eq "chebyshev" && column("stable") == 1 ? column("trajectory_error") : NaN) with points linestyle 2 title "chebyshev", \
     $front_trajectory using 1:2 with lines linecolor rgb "black" title "Pareto front", \
     $front_trajectory using 1:2:3 with labels left offset 0.5,0.3 font ",7" notitle
unset multiplot
