# The pelvis height of Cassie's passive drop on both sides (docs/simulation.md, "Side by side with
# MuJoCo"): the CSV of `mbgen_sim_vs_mujoco --csv`, one column per run (MuJoCo first), every ms.
#   gnuplot -e "csv='pelvis.csv'; png='out.png'; plot_title='...'" scripts/plot_sim_vs_mujoco.gp
set datafile separator ","
set datafile missing ""
set terminal pngcairo size 1000,650 font ",10" noenhanced
set output png
set grid
set key bottom left
set title plot_title
set xlabel "t [s]"
set ylabel "pelvis height [m]"
stats csv using 1 nooutput
columns = STATS_columns
plot for [i=2:columns] csv using 1:i with lines lw (i == 2 ? 3 : 1.5) title columnhead(i)
