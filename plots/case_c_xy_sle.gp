# Surface location error and forced vibration under the lobes, written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot case_c_xy_sle.gp
# It reads case_c_xy_sle.dat and writes case_c_xy_sle.png.

fs = 14
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'case_c_xy_sle.png'
set encoding utf8
set datafile missing '?'
data = 'case_c_xy_sle.dat'
set grid lc rgb '#d9d9d9' lw 0.6
set border lw 0.8
set multiplot layout 2,1 title 'Case C with the mode along X and Y (finishing pass example): 2 mm, 0.05 mm/tooth' noenhanced font ','.(fs+2) margins 0.09,0.97,0.08,0.91 spacing 0,0.06
set xrange [5000:25000]
set key top right opaque box lc rgb '#d9d9d9' font ','.(fs-3)
set format x ''
set ylabel 'depth (mm)'
set yrange [0:11.448265]
set arrow from graph 0, first 2 to graph 1, first 2 nohead lw 1.6 dt 2 lc rgb '#d62728'
set label 'this cut: 2 mm' at graph 0.01, first 2 offset 0,0.7 tc rgb '#d62728' font ','.(fs-3)
plot data index 0 using 1:2 with lines lw 2 lc rgb '#d95f02' title 'stability limit (sdm)'
unset arrow
unset label
set format x '%g'
set xlabel 'spindle speed (rev/min)'
set ylabel 'µm'
set autoscale y
set offsets 0, 0, graph 0.2, graph 0.05
plot data index 1 using 1:2 with lines lw 2.4 lc rgb '#202020' title 'surface location error (+ = material left)', \
     data index 1 using 1:3 with lines lw 1.2 lc rgb '#1f77b4' title 'peak to peak x', \
     data index 1 using 1:4 with lines lw 1.2 lc rgb '#ff7f0e' title 'peak to peak y', \
     data index 1 using 1:5 with points pt 6 ps 0.9 lc rgb '#d62728' title 'teeth leave the cut (linear model not valid)'
unset multiplot
