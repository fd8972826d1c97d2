#!/bin/sh
# Builds DXVK's d3d9.dll (64-bit) from a DXVK checkout, for `pointillist conform --d3d9`.
#
#   crates/conformance/dxvk/build-dxvk.sh DXVK_CHECKOUT [BUILD_DIR]
#
# DXVK_CHECKOUT: a DXVK source tree with its four submodules checked out
# (include/native/directx, include/vulkan, include/spirv, subprojects/libdisplay-info) at the
# commits its tag records. Tested with tag v2.6.2; 2.7 and later need Vulkan features Debian
# 12's lavapipe lacks. BUILD_DIR defaults to DXVK_CHECKOUT/build.pointillist.
# Needs the Debian packages: meson ninja-build glslang-tools g++-mingw-w64-x86-64-posix.
# Prints the built DLL's path on its last line.
set -eu

if [ $# -lt 1 ] || [ $# -gt 2 ]; then
    echo "usage: $0 DXVK_CHECKOUT [BUILD_DIR]" >&2
    exit 2
fi
src=$(cd "$1" && pwd)
build=${2:-$src/build.pointillist}

for f in meson.build src/d3d9/meson.build include/vulkan/include/vulkan/vulkan_core.h \
    include/spirv/include/spirv/unified1/spirv.hpp subprojects/libdisplay-info/meson.build; do
    if [ ! -f "$src/$f" ]; then
        echo "error: $src/$f missing: not a DXVK checkout with its submodules" >&2
        exit 1
    fi
done
for tool in meson ninja glslangValidator x86_64-w64-mingw32-gcc-posix x86_64-w64-mingw32-g++-posix; do
    if ! command -v "$tool" >/dev/null 2>&1; then
        echo "error: $tool not found; apt-get install meson ninja-build glslang-tools g++-mingw-w64-x86-64-posix" >&2
        exit 1
    fi
done

mkdir -p "$build"
build=$(cd "$build" && pwd)
# DXVK's build-win64.txt, naming the -posix compilers (DXVK needs win32 threads' posix
# flavour; this avoids changing the system's update-alternatives).
cross=$build/build-win64-posix.txt
cat > "$cross" <<'CROSS'
[binaries]
c = 'x86_64-w64-mingw32-gcc-posix'
cpp = 'x86_64-w64-mingw32-g++-posix'
ar = 'x86_64-w64-mingw32-ar'
strip = 'x86_64-w64-mingw32-strip'
windres = 'x86_64-w64-mingw32-windres'

[properties]
needs_exe_wrapper = true

[host_machine]
system = 'windows'
cpu_family = 'x86_64'
cpu = 'x86_64'
endian = 'little'
CROSS

if [ ! -f "$build/build.ninja" ]; then
    meson setup --cross-file "$cross" --buildtype release \
        -Denable_dxgi=false -Denable_d3d8=false -Denable_d3d10=false -Denable_d3d11=false \
        "$build" "$src"
fi
ninja -C "$build" src/d3d9/d3d9.dll
echo "$build/src/d3d9/d3d9.dll"
