# gyroflip figure: Compensated output
# Data: comp_K.dat (x y [low high]), one file per series. Restyle and run again with: gnuplot comp.gp
set encoding utf8
set style line 100 lc rgb '#d9d9d9' lw 1
set grid xtics ytics mxtics mytics ls 100, ls 100
set border 3 lw 1.2
set tics nomirror out
set mxtics
set mytics
set key below left vertical maxrows 1 width 2 box lc rgb '#bbbbbb' samplen 2 spacing 1.1
set title "Compensated output\n6 cycles: mean 0.000 °/s, std 0.00187 °/s (eqn 12)" noenhanced
set xlabel "time (s)\n" noenhanced
set ylabel 'compensated rate (°/s)' noenhanced
set offsets 0, 0, graph 0.05, graph 0.05

set terminal svg size 1100,680 font 'DejaVu Sans,12' enhanced background rgb 'white'
set output 'comp.svg'
plot 'comp_1.dat' using 1:2 with points pt 7 ps 0.5 lc rgb '#0072B2' title 'w = r − ΔN per cycle' noenhanced, \
     'comp_2.dat' using 1:2 with lines lw 2 lc rgb '#D55E00' title 'mean' noenhanced
unset output
