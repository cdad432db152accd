# Stability-lobe diagram, written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot turning_insert_lead_angle_lobes.gp
# It reads turning_insert_lead_angle_lobes.dat and writes turning_insert_lead_angle_lobes.png (both by relative name).

fs = 14   # base font size (pt); title, key and labels are relative to it
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'turning_insert_lead_angle_lobes.png'
set encoding utf8
set datafile missing '?'
data = 'turning_insert_lead_angle_lobes.dat'

# Values from the engine (mm, rev/min)
y_max = 20          # top of the depth axis
depth_max = 20      # deepest cut searched

# Colours
c_stable = '#8cc97e'; c_chatter = '#f08a7e'
c_envelope = '#1a4d80'; c_lobe = '#606a6a6a'; c_abs = '#c0392b'

set multiplot title 'Turning insert: lead angle 75 deg, nose radius 0.8 mm (analytic)' noenhanced font ','.(fs+3)
set lmargin at screen 0.085; set rmargin at screen 0.975
set tmargin at screen 0.85; set bmargin at screen 0.11
set key at screen 0.53, screen 0.895 center center horizontal reverse Left samplen 2 width -1 font ','.(fs-1)
set border lw 1 lc rgb '#404040'
set grid xtics ytics mxtics mytics back lw 1 lc rgb '#c8c8c8', lw 0.5 lc rgb '#e4e4e4'
set mxtics 2; set mytics 2
set xrange [1000:8000]
set yrange [0:y_max]
set ylabel 'depth of cut (mm)'
set xlabel 'spindle speed (rev/min)'
set style textbox opaque fc rgb '#50ffffff' noborder margins 1,1   # behind the lobe numbers
plot \
  data index 0 using 1:3:(depth_max > y_max ? depth_max : y_max) with filledcurves fs transparent solid 0.3 noborder fc rgb c_chatter title 'chatter', \
  data index 0 using 1:(0):3 with filledcurves fs transparent solid 0.4 noborder fc rgb c_stable title 'stable', \
  data index 0 using 1:($6 > 0 ? $3 : NaN) with lines lw 3 lc rgb c_envelope title 'stability limit'
unset multiplot
