# Draws convergence.png from convergence.csv (clothvk-bench). Run in this folder: gnuplot convergence.gp
if (!exists("out")) out = "convergence.png"
set terminal pngcairo noenhanced size 1500,500 font "sans,10"
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
set multiplot layout 1,3 title "enlarged.json, frozen substep of frame 0 on llvmpipe (LLVM 15.0.6, 256 bits), LP_NUM_THREADS=0"
set key bottom left
set format y "%.0e"
set title "residual vs iterations"
set xlabel "iterations"
set ylabel "residual (m²)"
set logscale x
set logscale y
plot "convergence.csv" using "iterations":(strcol("label") eq "jacobi" ? column("residual") : NaN) with linespoints linestyle 1 title "jacobi", \
     "convergence.csv" using "iterations":(strcol("label") eq "chebyshev" ? column("residual") : NaN) with linespoints linestyle 2 title "chebyshev", \
     "convergence.csv" using "iterations":(strcol("label") eq "rbgs" ? column("residual") : NaN) with linespoints linestyle 3 title "rbgs", \
     "convergence.csv" using "iterations":(strcol("label") eq "rbgs:1.7" ? column("residual") : NaN) with linespoints linestyle 4 title "rbgs ω=1.7", \
     "convergence.csv" using "iterations":(strcol("label") eq "gs-cpu" ? column("residual") : NaN) with linespoints linestyle 5 dashtype 2 title "gs-cpu", \
     6.76773835e-06 with lines linecolor rgb "black" dashtype 3 title "x* (converged)"
set title "solve error |x - x*| / |x* - x0|"
set ylabel "solve error"
set logscale x
set logscale y
plot "convergence.csv" using "iterations":(strcol("label") eq "jacobi" ? column("solve_error") : NaN) with linespoints linestyle 1 title "jacobi", \
     "convergence.csv" using "iterations":(strcol("label") eq "chebyshev" ? column("solve_error") : NaN) with linespoints linestyle 2 title "chebyshev", \
     "convergence.csv" using "iterations":(strcol("label") eq "rbgs" ? column("solve_error") : NaN) with linespoints linestyle 3 title "rbgs", \
     "convergence.csv" using "iterations":(strcol("label") eq "rbgs:1.7" ? column("solve_error") : NaN) with linespoints linestyle 4 title "rbgs ω=1.7", \
     "convergence.csv" using "iterations":(strcol("label") eq "gs-cpu" ? column("solve_error") : NaN) with linespoints linestyle 5 dashtype 2 title "gs-cpu"
set title "residual vs solve time (gs-cpu: host time)"
set xlabel "solve time per substep (ms)"
set ylabel "residual (m²)"
set logscale x
set logscale y
plot "convergence.csv" using "solve_ms":(strcol("label") eq "jacobi" ? column("residual") : NaN) with linespoints linestyle 1 title "jacobi", \
     "convergence.csv" using "solve_ms":(strcol("label") eq "chebyshev" ? column("residual") : NaN) with linespoints linestyle 2 title "chebyshev", \
     "convergence.csv" using "solve_ms":(strcol("label") eq "rbgs" ? column("residual") : NaN) with linespoints linestyle 3 title "rbgs", \
     "convergence.csv" using "solve_ms":(strcol("label") eq "rbgs:1.7" ? column("residual") : NaN) with linespoints linestyle 4 title "rbgs ω=1.7", \
     "convergence.csv" using "solve_ms":(strcol("label") eq "gs-cpu" ? column("residual") : NaN) with linespoints linestyle 5 dashtype 2 title "gs-cpu", \
     6.76773835e-06 with lines linecolor rgb "black" dashtype 3 title "x* (converged)"
unset multiplot
