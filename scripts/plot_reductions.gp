# The model-reduction chart of mbgen_study (docs/study.md):
#   gnuplot -e "dat='reductions.dat'; png='study_reductions.png'; plot_title='...'" scripts/plot_reductions.gp
# dat holds one line per reduction: speed-up over the whole model, error against the reference,
# and the reduction's name (quoted). The whole model sits at speed-up 1: its error is the
# integrator's; a reduction above it costs accuracy, one to its right gains speed.
set terminal pngcairo enhanced size 1000,750 font ",10"
set output png
set title plot_title noenhanced
set logscale y
set format y "10^{%L}"
set xlabel "speed-up over the whole model (CPU time per simulated second, same integrator and step)"
set ylabel "error: largest deviation from the whole model's reference [m, rad]"
set xrange [0.6:*]
set offsets 0, 1.0, 0, 0
set grid
unset key
# Labels above the even rows and below the odd ones: reductions of equal error stay readable.
plot dat using 1:2 with points pt 7 ps 2 lc rgb "#1f77b4", \
     dat every 2 using 1:2:3 with labels offset 0,1.5 center noenhanced, \
     dat every 2::1 using 1:2:3 with labels offset 0,-1.5 center noenhanced
