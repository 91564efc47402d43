# gyroflip figure: Bias
# Data: bias_K.dat (x y [low high]), one file per series. Restyle and run again with: gnuplot bias.gp
set encoding utf8
set style line 100 lc rgb '#d9d9d9' lw 1
set grid xtics ytics mxtics mytics ls 100, ls 100
set border 3 lw 1.2
set tics nomirror out
set mxtics
set mytics
set key below left vertical maxrows 1 width 2 box lc rgb '#bbbbbb' samplen 2 spacing 1.1
set title "Bias\nc = (y₀ + y₁₈₀)/2: the bias and its drift, which the flip removes" noenhanced
set xlabel "time (s)\n" noenhanced
set ylabel 'bias estimate c (°/s)' noenhanced
set offsets 0, 0, graph 0.05, graph 0.05

set terminal svg size 1100,680 font 'DejaVu Sans,12' enhanced background rgb 'white'
set output 'bias.svg'
plot 'bias_1.dat' using 1:2 with points pt 7 ps 0.5 lc rgb '#009E73' title 'c per cycle' noenhanced
unset output
