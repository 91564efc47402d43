# gyroflip figure: ΔN per run
# Data: runs_K.dat (x y [low high]), one file per series. Restyle and run again with: gnuplot runs.gp
set encoding utf8
set style line 100 lc rgb '#d9d9d9' lw 1
set grid xtics ytics mxtics mytics ls 100, ls 100
set border 3 lw 1.2
set tics nomirror out
set mxtics
set mytics
set key below left vertical maxrows 1 width 2 box lc rgb '#bbbbbb' samplen 2 spacing 1.1
set title "ΔN per run\n3 runs: mean 0.4000 °/s, std 0.010 °/s" noenhanced
set xlabel "run\n" noenhanced
set ylabel 'ΔN (°/s)' noenhanced
set xtics 1
set xrange [0.5:3.5]
set offsets 0, 0, graph 0.05, graph 0.05

set terminal svg size 1100,680 font 'DejaVu Sans,12' enhanced background rgb 'white'
set output 'runs.svg'
plot 'runs_1.dat' using 1:3:4 with filledcurves fs transparent solid 0.18 noborder lc rgb '#D55E00' title 'mean ± std' noenhanced, \
     'runs_2.dat' using 1:2 with lines lw 2 lc rgb '#D55E00' notitle, \
     'runs_3.dat' using 1:2:3:4 with yerrorbars pt 7 ps 0.7 lw 1.2 lc rgb '#0072B2' title 'ΔN ± correlated standard error' noenhanced
unset output
