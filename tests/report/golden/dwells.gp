# gyroflip figure: Output at 0° and 180°
# Data: dwells_K.dat (x y [low high]), one file per series. Restyle and run again with: gnuplot dwells.gp
set encoding utf8
set style line 100 lc rgb '#d9d9d9' lw 1
set grid xtics ytics mxtics mytics ls 100, ls 100
set border 3 lw 1.2
set tics nomirror out
set mxtics
set mytics
set key below left vertical maxrows 1 width 2 box lc rgb '#bbbbbb' samplen 2 spacing 1.1
set title "Output at 0° and 180°" noenhanced
set xlabel "time (s)\n" noenhanced
set ylabel 'dwell mean (°/s)' noenhanced
set offsets 0, 0, graph 0.05, graph 0.05

set terminal svg size 1100,680 font 'DejaVu Sans,12' enhanced background rgb 'white'
set output 'dwells.svg'
plot 'dwells_1.dat' using 1:2 with points pt 7 ps 0.5 lc rgb '#0072B2' title 'at 0°' noenhanced, \
     'dwells_2.dat' using 1:2 with points pt 7 ps 0.5 lc rgb '#D55E00' title 'at 180°' noenhanced
unset output
