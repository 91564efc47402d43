# gyroflip figure: Allan deviation
# Data: allan_K.dat (x y [low high]), one file per series. Restyle and run again with: gnuplot allan.gp
set encoding utf8
set style line 100 lc rgb '#d9d9d9' lw 1
set grid xtics ytics mxtics mytics ls 100, ls 100
set border 3 lw 1.2
set tics nomirror out
set mxtics
set mytics
set key below left vertical maxrows 1 width 2 box lc rgb '#bbbbbb' samplen 2 spacing 1.1
set title "Allan deviation\nupper limits, not drawn: B < 0.000400 °/s; K < 0.0000200 °/s·√Hz" noenhanced
set xlabel "averaging time τ (s)\n" noenhanced
set ylabel 'Allan deviation (°/s)' noenhanced
set logscale x 10
set format x '10^{%L}'
set logscale y 10
set format y '10^{%L}'
set xrange [1:10000]
set yrange [0.0001:0.1]
set label 1 'N' at 1,0.01 left front tc rgb '#0072B2' point pt 6 ps 1.6 lw 2 lc rgb '#0072B2' offset 1,1 noenhanced

set terminal pngcairo size 1100,680 font 'DejaVu Sans,12' enhanced
set output 'allan.png'
plot 'allan_1.dat' using 1:2:3:4 with yerrorbars pt 7 ps 0.7 lw 1.2 lc rgb '#0072B2' title 'compensated' noenhanced, 'allan_1.dat' using 1:2 with lines lw 1 lc rgb '#0072B2' notitle, \
     'allan_2.dat' using 1:2 with lines lw 2 dt 2 lc rgb '#0072B2' title 'N = 0.0100 °/s/√Hz (at τ = 1 s)' noenhanced
unset output

set terminal svg size 1100,680 font 'DejaVu Sans,12' enhanced background rgb 'white'
set output 'allan.svg'
plot 'allan_1.dat' using 1:2:3:4 with yerrorbars pt 7 ps 0.7 lw 1.2 lc rgb '#0072B2' title 'compensated' noenhanced, 'allan_1.dat' using 1:2 with lines lw 1 lc rgb '#0072B2' notitle, \
     'allan_2.dat' using 1:2 with lines lw 2 dt 2 lc rgb '#0072B2' title 'N = 0.0100 °/s/√Hz (at τ = 1 s)' noenhanced
unset output

set terminal pdfcairo size 7in,4.3in font 'DejaVu Sans,10' enhanced
set output 'allan.pdf'
plot 'allan_1.dat' using 1:2:3:4 with yerrorbars pt 7 ps 0.7 lw 1.2 lc rgb '#0072B2' title 'compensated' noenhanced, 'allan_1.dat' using 1:2 with lines lw 1 lc rgb '#0072B2' notitle, \
     'allan_2.dat' using 1:2 with lines lw 2 dt 2 lc rgb '#0072B2' title 'N = 0.0100 °/s/√Hz (at τ = 1 s)' noenhanced
unset output
