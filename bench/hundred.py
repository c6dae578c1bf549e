#!/usr/bin/env python3
"""Prints a scenario of 100 SDVs (25 per lane of a 4-lane, 3 km road, each with the standard
driving tree at its own speed) running for 120 s: the large run of bench/view_load.sh."""
print('import "std/drive.sdv"\n\nroad four_lanes {\n    lanes 4 forward\n    straight 3000 m\n}\n')
print('scenario hundred {\n    road four_lanes\n    timeout 120 s')
n = 0
for lane in range(1, 5):
    for k in range(25):
        n += 1
        speed = 8 + 2 * lane
        print(f'    vehicle c{n}: sdv {{\n        start lane {lane} at {20 + 45 * k} m\n        speed {speed} m/s\n'
              f'        tree std.drive(speed = {speed + k % 3} m/s)\n    }}')
print('    expect no_collision()\n}')
