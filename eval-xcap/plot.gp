# gnuplot script written by saccade eval; run: gnuplot plot.gp (in this folder)
set datafile separator ','
set terminal pngcairo size 900,600
set grid
set key outside right
names = 'saccade saccade-strict saccade-no-colour hough-colour-gate 10 saccade-ungated '
swept = ''
set xlabel 'distance threshold (cm)'
set output 'thresholds_tp.png'
set ylabel 'true positives'
plot for [n in names] 'thresholds.csv' using ($2*100):(strcol(1) eq n ? $3 : 1/0) with linespoints title n
set output 'thresholds_fp.png'
set ylabel 'false positives'
plot for [n in names] 'thresholds.csv' using ($2*100):(strcol(1) eq n ? $4 : 1/0) with linespoints title n
set output 'sweep.png'
set xlabel 'fovea distance from the object (cm)'
set ylabel 'true positives'
if (strlen(swept) > 0) { plot for [n in swept] 'sweep.csv' using ($2*100):(strcol(1) eq n ? $3 : 1/0) with linespoints title n } else { set xrange [0:35]; set yrange [0:1]; set label 'no sweep (--sweep)' at graph 0.4,0.5; plot 2 notitle }
set output 'sweep_attention.png'
set ylabel 'frames until found, attention loop (mean over scenes found)'
if (strlen(swept) > 0) { plot for [n in swept] 'sweep.csv' using ($2*100):(strcol(1) eq n && $6 > 0 ? $7 : 1/0) with linespoints title n } else { plot 2 notitle }
