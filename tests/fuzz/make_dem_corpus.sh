#!/usr/bin/env bash
# Writes the DEM harness's seeds (tests/fuzz/corpus/dem/) with GDAL's own tools: tiny rasters in
# the formats real DEMs come in. Each seed is one byte that picks the file name (hence the GDAL
# driver; the order of kNames in dem_fuzzer.cpp) followed by the file's bytes.
# Usage: tests/fuzz/make_dem_corpus.sh   (needs gdal-bin)
set -euo pipefail
cd "$(dirname "$0")"
out=corpus/dem
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"

# seed NAME SELECTOR FILE: the selector byte, then the file.
seed() { { printf "\\x$(printf %02x "$2")"; cat "$3"; } > "$out/$1"; }

# A 6 x 5 ramp in metres with one void (nodata -9999), as an ASCII grid.
cat > "$work/ramp.asc" <<'GRID'
ncols 6
nrows 5
xllcorner 500000
yllcorner 5200000
cellsize 30
NODATA_value -9999
100 102 104 106 108 110
103 105 107 -9999 111 113
106 108 110 112 114 116
109 111 113 115 117 119
112 114 116 118 120 122
GRID
seed ascii_grid.bin 1 "$work/ramp.asc"

# The same grid as GeoTIFFs: projected (UTM 33N) Float32, and geographic Int16 deflated with a
# scale and offset.
gdal_translate -q -of GTiff -a_srs EPSG:32633 -ot Float32 "$work/ramp.asc" "$work/utm.tif"
seed utm_float32.bin 0 "$work/utm.tif"
gdal_translate -q -of GTiff -a_srs EPSG:4326 -a_ullr -71.3 44.3 -71.2 44.2 -ot Int16 -a_scale 0.5 -a_offset 100 \
  -co COMPRESS=DEFLATE "$work/ramp.asc" "$work/geographic.tif"
seed geographic_int16_deflate.bin 0 "$work/geographic.tif"

# USGS ASCII DEM (its header carries the CRS), from the geographic grid.
gdal_translate -q -of USGSDEM -ot Int16 "$work/geographic.tif" "$work/ramp.dem" 2>/dev/null || true
[ -s "$work/ramp.dem" ] && seed usgs_ascii.bin 2 "$work/ramp.dem"

# ASCII gridded XYZ (no CRS: the loader's error path).
gdal_translate -q -of XYZ "$work/ramp.asc" "$work/ramp.xyz"
seed xyz.bin 4 "$work/ramp.xyz"

ls -l "$out"
