#!/bin/bash
# The machine's CPU counters every 5 s (epoch, the cpu line of /proc/stat), for bench/packing.py --load
while true; do echo "$(date +%s) $(head -1 /proc/stat)"; sleep 5; done
