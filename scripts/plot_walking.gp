# The walking experiment's charts (mbgen_walk, docs/control.md):
#   gnuplot -e "dir='out'; walk='straight'; bound=0" scripts/plot_walking.gp
# One PNG per walk, <dir>/walking_<walk>.png, the five configurations overlaid: the smallest
# self-distance between the legs and between an arm and the rest, the smallest margin to the
# description's joint ranges, the vertical angular momentum about the CoM, the ground's yaw torque
# about the vertical through the ZMP (again, zoomed, for the three that track the momentum), and how far the full-body ZMP is from the pattern's (the
# pattern's CoM corrected for the configuration "both", the qp configuration's for itself). The y
# ranges are fixed: a run that leaves them is cut at the edge.
set datafile separator ","
set terminal pngcairo size 1000,1600 font ",10" noenhanced
set output sprintf("%s/walking_%s.png", dir, walk)
set grid
set key outside right top vertical
configs = "plain avoidance momentum both qp"
colors = "#1f77b4 #d62728 #2ca02c #9467bd #ff7f0e"
n = words(configs)
csv(c) = sprintf("%s/walk_%s_%s.csv", dir, walk, c)
set multiplot layout 7,1 title sprintf("Lola walking (%s): IK at 1 kHz on the generated code", walk)
set xlabel "t [s]"
set yrange [-10:40]
set ylabel "legs: min distance [mm]"
plot for [i=1:n] csv(word(configs, i)) using "t":(1000*column("d_legs")) with lines lw 2 lc rgb word(colors, i) title word(configs, i), \
     1000*bound with lines dt 2 lc rgb "black" title "bound", \
     5 with lines dt 3 lc rgb "#ff7f0e" title "qp: 5 mm"
set yrange [-10:80]
set ylabel "arm-body: min distance [mm]"
plot for [i=1:n] csv(word(configs, i)) using "t":(1000*column("d_arms")) with lines lw 2 lc rgb word(colors, i) title word(configs, i), \
     1000*bound with lines dt 2 lc rgb "black" title "bound"
set ylabel "joint-range margin [rad, m]"
set yrange [-0.5:0.1]
plot for [i=1:n] csv(word(configs, i)) using "t":"limit_margin" with lines lw 2 lc rgb word(colors, i) title word(configs, i), \
     0 with lines dt 2 lc rgb "black" title "range"
set yrange [-3:3]
set ylabel "k_z about CoM [kg m^2/s]"
plot for [i=1:n] csv(word(configs, i)) using "t":"k_z" with lines lw 2 lc rgb word(colors, i) title word(configs, i)
set yrange [-50:50]
set ylabel "ground yaw torque [N m]"
plot for [i=1:n] csv(word(configs, i)) using "t":"yaw_torque" with lines lw 2 lc rgb word(colors, i) title word(configs, i)
set yrange [-2:2]
set ylabel "the same, momentum tracked [N m]"
plot for [i=3:n] csv(word(configs, i)) using "t":"yaw_torque" with lines lw 2 lc rgb word(colors, i) title word(configs, i)
set yrange [0:60]
set ylabel "full-body ZMP error [mm]"
plot for [i=1:n] csv(word(configs, i)) using "t":(1000*column("zmp_error")) with lines lw 2 lc rgb word(colors, i) title word(configs, i)
unset multiplot
