# The closure drift chart of mbgen_study (docs/study.md):
#   gnuplot -e "dat='closure_drift.dat'; png='study_closure_drift.png'; plot_title='...'" scripts/plot_closure_drift.gp
# dat holds one block per variant (a quoted title line, then time, max |Phi|).
stats dat using 1 nooutput  # before any range: it counts the blocks
blocks = STATS_blocks
set terminal pngcairo enhanced size 1000,750 font ",10"
set output png
set title plot_title noenhanced
set logscale y
set format y "10^{%L}"
set xlabel "t [s]"
set ylabel "loop violation max |{/Symbol F}| [m, rad]"
set yrange [1e-17:*]
set grid
set key below noenhanced maxrows 4
plot for [i=0:blocks-1] dat index i using 1:2 with lines lw 2 title columnheader(1), \
     1e-10 with lines dt 2 lc rgb "gray40" title "1e-10: the simulator's claim"
