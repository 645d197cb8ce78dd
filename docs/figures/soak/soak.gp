# Draws soak.png from soak.csv (scripts/soak.py). Run in this folder: gnuplot soak.gp
if (!exists("out")) out = "soak.png"
set terminal pngcairo noenhanced size 800,400 font "sans,10"
set output out
set datafile separator ","
set title "drape.json 24x24, 100,000 frames, lavapipe: resident and device memory"
set xlabel "frame"
set ylabel "MB"
set xrange [0:100000]
set yrange [0:200]
set key bottom right
plot "soak.csv" using 1:3 skip 1 with lines linewidth 2 title "resident (RSS)", \
     "" using 1:4 skip 1 with lines linewidth 2 title "device memory"
