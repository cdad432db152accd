# Receptance (FRF) chart, written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot turning_insert_lead_angle_frf.gp
# It reads turning_insert_lead_angle_frf.dat and writes turning_insert_lead_angle_frf.png (both by relative name).

fs = 14   # base font size (pt); title, key and labels are relative to it
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'turning_insert_lead_angle_frf.png'
set encoding utf8
set datafile missing '?'
data = 'turning_insert_lead_angle_frf.dat'

# Colours
c_tool = '#1f77b4'; c_workpiece = '#e07b00'; c_relative = '#202020'
# Column of body b (0 tool, 1 workpiece, 2 relative), term t (0 xx, 1 yy), part p
# (0 magnitude, 1 phase, 2 real, 3 imaginary)
col(b, t, p) = 2 + 12*t + 4*b + p

set multiplot title 'Turning insert: lead angle 75 deg, nose radius 0.8 mm' noenhanced font ','.(fs+3)
set lmargin at screen 0.11; set rmargin at screen 0.975
set border lw 1 lc rgb '#404040'
set grid xtics ytics mxtics mytics back lw 1 lc rgb '#c8c8c8', lw 0.5 lc rgb '#e4e4e4'
set xrange [50.33:300]
set mxtics 2
set key at screen 0.54, screen 0.9 center center horizontal reverse Left samplen 2 width -1 font ','.(fs-1)

# Upper panel
set tmargin at screen 0.86; set bmargin at screen 0.515
set format x ''; unset xlabel
set logscale y
set format y '10^{%L}'
set mytics 10
set ylabel 'magnitude |G| (m/N)'
plot \
  data using 1:col(2,0,0) with lines lw 3.2 lc rgb c_relative title 'relative = tool + workpiece xx', \
  data using 1:col(1,0,0) with lines lw 1.6 lc rgb c_workpiece title 'workpiece xx', \
  data using 1:col(0,0,0) with lines lw 1.6 lc rgb c_tool title 'tool xx', \
  data using 1:col(2,1,0) with lines lw 3.2 dt (6,4) lc rgb c_relative title 'relative = tool + workpiece yy', \
  data using 1:col(1,1,0) with lines lw 1.6 dt (6,4) lc rgb c_workpiece title 'workpiece yy', \
  data using 1:col(0,1,0) with lines lw 1.6 dt (6,4) lc rgb c_tool title 'tool yy'

# Lower panel
unset key
set tmargin at screen 0.465; set bmargin at screen 0.10
set format x '%g'
set xlabel 'frequency (Hz)'
unset logscale y
set format y '%g'
set yrange [-180:0]
set ytics 45
set mytics 3
set ylabel 'phase (deg)'
plot \
  data using 1:col(2,0,1) with lines lw 3.2 lc rgb c_relative title 'relative = tool + workpiece xx', \
  data using 1:col(1,0,1) with lines lw 1.6 lc rgb c_workpiece title 'workpiece xx', \
  data using 1:col(0,0,1) with lines lw 1.6 lc rgb c_tool title 'tool xx', \
  data using 1:col(2,1,1) with lines lw 3.2 dt (6,4) lc rgb c_relative title 'relative = tool + workpiece yy', \
  data using 1:col(1,1,1) with lines lw 1.6 dt (6,4) lc rgb c_workpiece title 'workpiece yy', \
  data using 1:col(0,1,1) with lines lw 1.6 dt (6,4) lc rgb c_tool title 'tool yy'
unset multiplot
