#!/usr/bin/env bash
# Installs hedra from the build tree into a temporary prefix, builds examples/downstream
# against it with find_package(hedra) and runs it; then the same program through pkg-config.
# Usage: install_test.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
src=$1
build=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix

cmake --install "$build" --prefix "$prefix" > "$tmp/install.log"
for f in include/hedra/hedra.h include/hedra/version.h include/hedra/core/body.h \
         include/hedra/io/mesh_io.h include/hedra/render/svg.h \
         lib/cmake/hedra/hedraConfig.cmake lib/cmake/hedra/hedraConfigVersion.cmake \
         lib/pkgconfig/hedra.pc lib/libhedra_kernel.a bin/hedra; do
  [ -e "$prefix/$f" ] || { echo "install_test: $f missing from the install prefix"; exit 1; }
done
# Private headers and baselines stay out of the installed API.
[ ! -e "$prefix/include/hedra/baselines" ] || { echo "install_test: baselines installed"; exit 1; }
[ ! -e "$prefix/include/visibility" ] || { echo "install_test: private headers installed"; exit 1; }
"$prefix/bin/hedra" --version | grep -q '^hedra [0-9]*\.[0-9]*\.[0-9]*$'

expect() {  # the downstream program's output
  grep -qx "convex 0" "$1" && grep -qx "pieces 2" "$1" && grep -qx "volume 12" "$1" &&
    grep -qx "svg 1" "$1" && grep -q "^visible [1-9]" "$1" || { cat "$1"; exit 1; }
}

# CMake: find_package(hedra REQUIRED), target_link_libraries(app PRIVATE hedra::hedra).
cmake -S "$src/examples/downstream" -B "$tmp/app" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$prefix" > "$tmp/configure.log"
cmake --build "$tmp/app" > "$tmp/build.log" 2>&1 || { cat "$tmp/build.log"; exit 1; }
"$tmp/app/app" "$tmp/app.svg" > "$tmp/out.txt"
expect "$tmp/out.txt"
grep -q "<svg" "$tmp/app.svg"

# examples/ builds the same way against the installed package.
cmake -S "$src/examples" -B "$tmp/examples" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$prefix" > "$tmp/configure-examples.log"
cmake --build "$tmp/examples" > "$tmp/build-examples.log" 2>&1 || { cat "$tmp/build-examples.log"; exit 1; }
"$tmp/examples/example_body_matrix" | grep -q "L convex: 0, volume 12"

# pkg-config.
PKG_CONFIG_PATH="$prefix/lib/pkgconfig" c++ -O1 -o "$tmp/app_pc" "$src/examples/downstream/app.cpp" \
  $(PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config --cflags --libs hedra)
"$tmp/app_pc" > "$tmp/out_pc.txt"
expect "$tmp/out_pc.txt"
echo "install_test: installed, found with find_package and pkg-config, downstream program and examples ran"
