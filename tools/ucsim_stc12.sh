#!/usr/bin/env bash
# ucsim_stc12.sh: build s51 with the STC12C5A60S2 model (sim/ucsim/) into build/ucsim/s51 from
# Debian's sdcc source package, fetched with the project's own apt configuration; the system's
# /usr/bin/s51 stays as it is. Quick when the build is up to date with sim/ucsim/.
set -euo pipefail
cd "$(dirname "$0")/.."
out=build/ucsim
model=(sim/ucsim/stc12.cc sim/ucsim/stc12_hw.cc sim/ucsim/stc12_link.cc sim/ucsim/stc12cl.h sim/ucsim/stc12_link.h)
src_files=(sim/ucsim/stc12.patch "${model[@]}" sim/ucsim/sources.list.in tools/ucsim_stc12.sh)
stamp=$(cat "${src_files[@]}" | sha1sum | cut -c1-16)
if [ -x $out/s51 ] && [ "$(cat $out/.stamp 2>/dev/null)" = "$stamp" ]; then
    exit 0
fi
say() { echo "ucsim_stc12: $*"; }
sudo=""
[ "$(id -u)" = 0 ] || sudo="sudo"
need=()
for t in bison flex g++ make patch xz; do command -v $t >/dev/null 2>&1 || need+=("$t"); done
if [ ${#need[@]} -gt 0 ]; then
    pk=(); for t in "${need[@]}"; do case $t in xz) pk+=(xz-utils);; *) pk+=("$t");; esac; done
    say "installing ${pk[*]} (apt)"
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${pk[@]}" >/dev/null
fi
mkdir -p $out/apt/lists/partial $out/apt/parts $out/src
codename=$(. /etc/os-release && echo "${VERSION_CODENAME:-bookworm}")
sed "s/@CODENAME@/$codename/" sim/ucsim/sources.list.in > $out/apt/sources.list
apto=(-o Dir::Etc::SourceParts="$PWD/$out/apt/parts" -o Dir::Etc::SourceList="$PWD/$out/apt/sources.list"
      -o Dir::State::Lists="$PWD/$out/apt/lists" -o Debug::NoDropPrivs=true)
tarball=$(ls $out/src/sdcc_*.orig.tar.* 2>/dev/null | head -1 || true)
if [ -z "$tarball" ]; then
    say "fetching Debian's sdcc source (apt-get source, the project's own list)"
    apt-get "${apto[@]}" update -qq
    (cd $out/src && apt-get "${apto[@]}" source --download-only -qq sdcc >/dev/null 2>&1) || {
        echo "ucsim_stc12: FAILED to fetch the sdcc source package" >&2; exit 1; }
    tarball=$(ls $out/src/sdcc_*.orig.tar.* | head -1)
fi
tree=$out/tree
rm -rf $tree && mkdir -p $tree
say "unpacking sim/ucsim of $(basename "$tarball")"
tar xf "$tarball" -C $tree --strip-components=3 --wildcards '*/sim/ucsim/*'
cp "${model[@]}" $tree/s51.src/
patch -s -d $tree -p1 < sim/ucsim/stc12.patch
ports=""
for p in ds390 avr z80 z180 gbz80 r2k r3ka tlcs m68hc08 s08 xa stm8 pdk st7 p1516 m6809 m6800 m68hc11 mos6502 rxk pblaze; do
    ports="$ports --disable-$p-port"
done
say "configure and build s51 (under a minute)"
(cd $tree && ./configure $ports --disable-serio > ../configure.log 2>&1) || {
    echo "ucsim_stc12: configure FAILED ($out/configure.log)" >&2; exit 1; }
# s51 and the four libraries it links, not uCsim's other programs and libraries; no debugging
# information (uCsim's default -g -ggdb takes a third of the compile)
(cd $tree && make -C s51.src -j2 CXXFLAGS="-O2 -pipe -Wall -Wno-overloaded-virtual" > ../make.log 2>&1) || {
    echo "ucsim_stc12: build FAILED ($out/make.log)" >&2; tail -20 $out/make.log >&2; exit 1; }
cp $tree/s51.src/s51 $out/s51.new && mv -f $out/s51.new $out/s51     # a run may hold the old one
echo "$stamp" > $out/.stamp
say "$out/s51 ready (-t STC12)"
