#!/bin/sh
# Installs the build tree BUILD_DIR into a temporary prefix, then builds
# tests/install/consumer.c against it twice, with find_package(SAM) and with
# pkg-config, and runs both; and configures the source tree SOURCE_DIR
# without the tests as if cmocka were not installed.
# Usage: run.sh BUILD_DIR WORK_DIR SOURCE_DIR
set -eu
build=$1
work=$2
source=$3
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"

echo "== find_package(SAM)"
cmake -S "$here" -B "$work/cmake" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release > "$work/configure.log"
cmake --build "$work/cmake" > "$work/build.log"
"$work/cmake/consumer"

echo "== pkg-config sam"
PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig" pkg-config --modversion sam
flags=$(PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig" pkg-config --static --cflags --libs sam)
cc -std=c11 -Wall -Wextra -Werror -o "$work/consumer_pc" "$here/consumer.c" $flags
# A shared build's libraries are found at run time as any library is.
LD_LIBRARY_PATH="$work/prefix/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" "$work/consumer_pc"

echo "== without the tests, cmocka hidden"
cmake -S "$source" -B "$work/notest" -DSAM_BUILD_TESTING=OFF -DCMAKE_DISABLE_FIND_PACKAGE_cmocka=ON \
    > "$work/notest.log"
echo "configured"

# What a user runs from the prefix: the programs.
"$work/prefix/bin/sam_build" --version
