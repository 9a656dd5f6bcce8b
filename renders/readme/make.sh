#!/usr/bin/env bash
# Regenerates the pictures README.md shows (run from the repository root after installing).
set -euo pipefail
for m in fourbar sixbar fivebar; do
  linkage render "$m" --out "renders/readme/$m.gif" --size 320x240 --fps 20
done
mkdir -p renders/readme/gallery
for m in $(linkage list | awk '{print $1}'); do
  linkage render "$m" --out "renders/readme/gallery/$m.gif" --size 240x180 --fps 12
done
linkage plot fourbar --out renders/readme/fourbar_sheet.png
linkage plot servo_press --out renders/readme/servo_press_sheet.png
