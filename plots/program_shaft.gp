# Program check, written by chatter 0.1.0.
# Reproduce or restyle: cd here and run gnuplot program_shaft.gp

fs = 14
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'program_shaft.png'
set encoding utf8
set datafile missing '?'
data = 'program_shaft.dat'
set multiplot layout 2,1 title 'shaft.ngc: 3 cutting blocks, 1 unstable, 0 overloaded' noenhanced font ','.(fs+2)
set grid lc rgb '#c8c8c8'
set key top right opaque box font ','.(fs-3)
set xlabel 'cutting time (s)'
set ylabel 'margin = limit / depth'
set yrange [0:4.2]
set y2label 'spindle power (kW)'
set y2tics
set ytics nomirror
set arrow 1 from graph 0, first 1 to graph 1, first 1 nohead lw 2 lc rgb '#c0392b' dt 2
plot data index 0 using 1:2 with lines lw 2.5 lc rgb '#1a4d80' title 'margin (limit / depth; 1 = chatter)', \
  data index 0 using 1:3 axes x1y2 with lines lw 1.5 lc rgb '#e07b00' title 'power (kW)', \
  7.5 axes x1y2 with lines dt 3 lc rgb '#e07b00' title 'machine power'
unset arrow 1
unset y2tics
unset y2label
set ytics mirror
set xlabel 'position along the bar from the chuck (mm)'
set ylabel 'margin'
set y2label 'diametral error (um)'
set y2tics
set ytics nomirror
set autoscale y
set yrange [0:4.2]
set autoscale y2
plot data index 1 using 1:2 with linespoints pt 7 ps 0.4 lw 2 lc rgb '#1a4d80' title 'margin (each pass)', \
  data index 1 using 1:3 axes x1y2 with linespoints pt 6 ps 0.4 lw 1.5 dt 2 lc rgb '#e07b00' title 'diametral error (um)', \
  1 with lines dt 2 lw 2 lc rgb '#c0392b' title 'chatter'
unset multiplot
