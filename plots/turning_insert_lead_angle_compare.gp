# Depth limit by method (chatter compare), written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot turning_insert_lead_angle_compare.gp
# It reads turning_insert_lead_angle_compare.dat and writes turning_insert_lead_angle_compare.png (both by relative name).

fs = 14   # base font size (pt); title, key and labels are relative to it
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'turning_insert_lead_angle_compare.png'
set encoding utf8
set datafile missing '?'
data = 'turning_insert_lead_angle_compare.dat'

# Values from the engine (mm, rev/min)
y_max = 20          # top of the depth axis
depth_max = 20      # deepest cut searched
# Columns of method m (0 = first): depth limit and bounded flag
col_depth(m) = 2 + 2*m
col_bounded(m) = 3 + 2*m
# A gap where a method has no limit (a NaN breaks the line; a '?' row would be joined across).
limit(m) = column(col_bounded(m)) > 0 ? column(col_depth(m)) : NaN

# Colours, one per method
c_m0 = '#8fbce6'   # analytic
c_m1 = '#0b3a6e'   # coupled
c_m2 = '#d95f02'   # sdm
c_flip = '#7b1fa2'; c_fold = '#00796b'   # where a limit is set by a flip / fold multiplier

set multiplot title 'Turning insert: lead angle 75 deg, nose radius 0.8 mm: depth limit by method' noenhanced font ','.(fs+3)
set lmargin at screen 0.085; set rmargin at screen 0.975
set tmargin at screen 0.85; set bmargin at screen 0.11
set key at screen 0.53, screen 0.895 center center horizontal reverse Left samplen 3 width 1 font ','.(fs-1)
set border lw 1 lc rgb '#404040'
set grid xtics ytics mxtics mytics back lw 1 lc rgb '#c8c8c8', lw 0.5 lc rgb '#e4e4e4'
set mxtics 2; set mytics 2
set xrange [1000:8000]
set yrange [0:y_max]
set xlabel 'spindle speed (rev/min)'
set ylabel 'depth limit (mm)'
plot \
  data index 0 using 1:(limit(0)) with lines lw 7 lc rgb c_m0 notitle, \
  data index 0 using 1:(limit(2)) with lines lw 3 lc rgb c_m2 notitle, \
  data index 0 using 1:(limit(1)) with lines lw 1.6 dt (6,4) lc rgb c_m1 notitle, \
  keyentry with lines lw 7 lc rgb c_m0 title 'analytic', \
  keyentry with lines lw 1.6 dt (6,4) lc rgb c_m1 title 'coupled', \
  keyentry with lines lw 3 lc rgb c_m2 title 'sdm', \
  keyentry with lines lt nodraw title sprintf('gap: no limit below %g mm', depth_max)
unset multiplot
