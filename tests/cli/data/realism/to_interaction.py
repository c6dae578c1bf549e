"""Writes the trajectories of sdv runs (trajectories.csv) as one INTERACTION track file at 10 Hz:
the synthetic recording of the calibration test. Usage: to_interaction.py OUT.csv RUN_DIR..."""
import csv
import math
import sys

with open(sys.argv[1], "w") as out:
    out.write("track_id,frame_id,timestamp_ms,agent_type,x,y,vx,vy,psi_rad,length,width\n")
    for run in sys.argv[2:]:
        for r in csv.DictReader(open(run + "/trajectories.csv")):
            tick = int(r["tick"])
            if tick % 3:
                continue
            yaw, v = float(r["yaw"]), float(r["speed"])
            out.write(f"{r['vehicle']},{tick // 3 + 1},{round(float(r['time']) * 1000)},car,{r['x']},{r['y']},"
                      f"{v * math.cos(yaw):.4f},{v * math.sin(yaw):.4f},{yaw},4.5,1.8\n")
