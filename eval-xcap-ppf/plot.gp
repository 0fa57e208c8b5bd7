# gnuplot script written by saccade eval; run: gnuplot plot.gp (in this folder)
set datafile separator ','
set terminal pngcairo size 1000,680 noenhanced font ',11'
set grid
set key below horizontal  # under the axes: the legend never hides a curve
set style data linespoints
set offsets 0, 0, graph 0.05, 0

# True and false positives as the distance threshold grows (the paper's Figs. 8, 9).
set xlabel 'distance threshold (cm)'
set xrange [0:10.5]
set arrow 1 from 8, graph 0 to 8, graph 1 nohead dashtype 2 linecolor 'gray40'
set yrange [0:60]
set output 'thresholds_tp.png'
set title "True positives against the distance threshold (60 scenes; dashed: the paper's 8 cm rule)"
set ylabel "true positives (scenes)"
plot 'thresholds.csv' using ($2*100):(strcol(1) eq "saccade" ? $3 : 1/0) title "saccade", \
     'thresholds.csv' using ($2*100):(strcol(1) eq "opencv-ppf" ? $3 : 1/0) title "opencv-ppf"
set yrange [0:*]
set output 'thresholds_fp.png'
set title "False positives against the distance threshold (60 scenes; dashed: the paper's 8 cm rule)"
set ylabel "false positives (detections)"
plot 'thresholds.csv' using ($2*100):(strcol(1) eq "saccade" ? $4 : 1/0) title "saccade", \
     'thresholds.csv' using ($2*100):(strcol(1) eq "opencv-ppf" ? $4 : 1/0) title "opencv-ppf"
