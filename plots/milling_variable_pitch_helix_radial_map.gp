# Floquet stability map (spectral radius), written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot milling_variable_pitch_helix_radial_map.gp
# It reads milling_variable_pitch_helix_radial_map.dat and writes milling_variable_pitch_helix_radial_map.png (both by relative name).

fs = 14   # base font size (pt); title, key and labels are relative to it
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'milling_variable_pitch_helix_radial_map.png'
set encoding utf8
set datafile missing '?'
data = 'milling_variable_pitch_helix_radial_map.dat'

# Colour scale: spectral radius from 1/rho_clip to rho_clip on a log axis, centred on 1
# (values beyond are drawn in the end colours).
rho_clip = 10
clip(r) = r < 1.0/rho_clip ? 1.0/rho_clip : (r > rho_clip ? rho_clip : r)

# Colours: contour pieces by multiplier type, key swatches
c_hopf = '#101010'; c_flip = '#7b1fa2'; c_fold = '#00796b'
c_stable = '#6fa3d2'; c_chatter = '#f0804a'
# Blues below rho = 1, oranges to reds above, with a step at 1.
set palette defined (0 '#0b3a6e', 0.25 '#3f7fbf', 0.5 '#bcd7ee', 0.5 '#fdc793', 0.75 '#ee7640', 1 '#7a0c0c')

set multiplot title '4-flute variable pitch, 30 deg helix, 12 mm, half slot climb: spectral radius (sdm) at 9000 rev/min' noenhanced font ','.(fs+3)
set lmargin at screen 0.085; set rmargin at screen 0.855
set tmargin at screen 0.83; set bmargin at screen 0.11
set key at screen 0.47, screen 0.885 center center horizontal reverse Left samplen 2 width -1 font ','.(fs-1)
set border lw 1 lc rgb '#404040' front
set tics front
set mxtics 2; set mytics 2
set xrange [0.6:12]
set yrange [0:20]
set xlabel 'radial depth of cut a_e (mm)'
set ylabel 'axial depth of cut a_p (mm)'
set logscale cb
set cbrange [1.0/rho_clip:rho_clip]
set colorbox user origin screen 0.875, screen 0.11 size screen 0.022, screen 0.72 front border
set cblabel 'spectral radius ρ' offset 0.5,0
set cbtics (sprintf('≤ %g', 1.0/rho_clip) 1.0/rho_clip, '0.2' 0.2, '0.5' 0.5, '1' 1, '2' 2, '5' 5, sprintf('≥ %g', rho_clip) rho_clip) out nomirror
set mcbtics 1
plot \
  data index 0 using 1:2:(clip($3)) with image notitle, \
  keyentry with boxes fs solid 1.0 noborder fc rgb c_stable title 'stable (ρ < 1)', \
  keyentry with boxes fs solid 1.0 noborder fc rgb c_chatter title 'chatter (ρ > 1)', \
  data index 1 using 1:(strcol(3) eq 'hopf' ? $2 : NaN) with lines lw 5.5 lc rgb '#50ffffff' notitle, \
  data index 1 using 1:(strcol(3) eq 'hopf' ? $2 : NaN) with lines lw 2.6 lc rgb c_hopf title 'ρ = 1, Hopf (complex μ)', \
  data index 2 using 1:(strcol(3) eq 'fold' ? $2 : NaN) with points pt 6 ps 0.7 lw 1.5 lc rgb c_fold title 'fold dominates (μ ≈ +1)', \
  data index 3 using 1:2 with points pt 7 ps 0.9 lc rgb '#ffffff' notitle, \
  data index 3 using 1:2 with points pt 7 ps 0.55 lc rgb '#000000' title 'limit search'
unset multiplot
