#!/usr/bin/env bash
# Build CONTACT (E.A.H. Vollebregt, Vtech CMCC; Apache-2.0; https://github.com/eve70a/CONTACT)
# with gfortran, for rollerrig's optional backend rollerrig.contact.cntc.
#
#   tools/build_contact.sh CONTACT_SOURCE INSTALL_DIR
#
# CONTACT_SOURCE is a checkout of CONTACT (the folder holding src/ and python_intfc/); this script
# downloads nothing and never copies CONTACT into rollerrig. INSTALL_DIR receives
#   bin/contact_addon_linux64.so   the library (the name CONTACT's python_intfc loads)
#   bin/contact_linux64            the stand-alone program (runs the .inp cases in examples/)
#   python_intfc/                  CONTACT's own Python interface, copied from the source
# then: export CONTACT_DIR=INSTALL_DIR.
#
# Needs: gfortran (with OpenMP) and LAPACK/BLAS (e.g. apt-get install gfortran liblapack-dev).
# Tested with gfortran 12.2 on Linux x86-64 and CONTACT commit d431cdb (2025-07-23, revision
# 2707): the program so built reproduces the total forces of examples/fastsim, tractcurv,
# cattaneo, carter2d, bentall, catt_to_cart and spence35 (.ref_out, made by CONTACT's own Intel
# build) to the printed digits; only iteration counts and timings differ. The version banner
# says "linux32" (gfortran's preprocessor does not define __x86_64__); the code is 64-bit.
#
# CONTACT's own makefile is written for Intel ifort and MKL. Differences here: gfortran, -O2,
# no MKL (WITH_MKLFFT undefined: CONTACT then uses its own FFT-free code paths; LAPACK's dgbsv,
# dpbsv from the system), no '-convert big_endian' (only unformatted files, which the Hertzian
# cases do not use), and the modules are compiled in dependency order by retrying until every
# one has compiled (the order of src/modules.incl, found instead of hard-coded). A dozen Intel
# extensions are patched, with sed, in a copy of the sources under INSTALL_DIR/src; each is
# named above its sed line below.
set -euo pipefail

if [ $# -ne 2 ]; then
    echo "usage: $0 CONTACT_SOURCE INSTALL_DIR" >&2
    exit 2
fi
command -v gfortran >/dev/null || { echo "$0: needs gfortran (e.g. apt-get install gfortran)" >&2; exit 1; }
PREFIX=$(mkdir -p "$2" && cd "$2" && pwd)
SRC="$PREFIX/src"
OBJ="$PREFIX/obj"
rm -rf "$SRC" "$OBJ"
mkdir -p "$OBJ" "$PREFIX/bin"
cp -r "$1/src" "$SRC"

# Intel extensions gfortran refuses, patched in the copy (the checkout stays as it is):
# omp_in_parallel() is LOGICAL but compared with / assigned to integers
sed -i 's/omp_in_parallel()/merge(1, 0, omp_in_parallel())/g' "$SRC"/*.f90
# a function defined without parentheses; OPEN(dispose=); ifport's ScanFolder (unused elsewhere)
sed -i -e 's/^function LicenseGetDebug *$/function LicenseGetDebug()/' \
    -e "s/, dispose='delete'//" -e '/public  *ScanFolder/d' \
    -e '/^subroutine ScanFolder/,/^end subroutine ScanFolder/d' "$SRC"/m_licensing.f90
# logicals compared with .ne.
sed -i 's/any(mask(\([^)]*\))\.ne\.mask(/any(mask(\1).neqv.mask(/' "$SRC"/m_bspline_make.f90
# m_gridfunc redeclares m_globals' strlen (= 16, the same value)
sed -i -e '/^ *private  *strlen *$/d' -e '/^ *integer, *parameter :: strlen *= *16 *$/d' \
    "$SRC"/m_gridfunc.f90
# test_fft is made public but exists only WITH_MKLFFT
sed -i '/^public  *test_fft *$/d' "$SRC"/m_snorm.f90
# an ASSOCIATE whose targets use its own names
sed -i 's/row1st => igs%row1st,   rowlst => igs%rowlst,/row1st => outpt%igs%row1st, rowlst => outpt%igs%rowlst,/' \
    "$SRC"/m_temperature.f90
# integer flags used as logicals in IF (ifort: odd = true; their values are 0, 1, -1)
sed -i 's/^      if (is_wheel) then$/      if (is_wheel.ne.0) then/' "$SRC"/m_varprof.f90
sed -i 's/^ *if (is_right) then$/               if (is_right.ne.0) then/' "$SRC"/m_wr_output.f90
sed -i 's/^   if (out_open) louttm = lout$/   if (out_open.ne.0) louttm = lout/' \
    "$SRC"/contact_addon.f90
# the exported names: gfortran's preprocessor is traditional (no # stringification), so
# CNAME_(a) becomes "a", which it expands inside strings; and #include wants double quotes
sed -i 's/^#define CNAME_(a) *STRINGIFY( a )$/#define CNAME_(a) "a"/' \
    "$SRC"/m_caddon_data.f90 "$SRC"/contact_addon.f90
sed -i "s/^#  include 'VERSION'$/#  include \"VERSION\"/" "$SRC"/contact_addon.f90

FFLAGS=(-cpp -O2 -fopenmp -fPIC -ffree-line-length-none -J"$OBJ" -I"$OBJ" -I"$SRC")
LIBS=(-llapack -lblas)  # dgbsv, dpbsv (MKL in CONTACT's own build)

# every module of src/ but the main programs, the test programs and the library's own file
mapfile -t todo < <(cd "$SRC" && ls m_*.f90 mkl_dfti.f90)
objs=()
while [ ${#todo[@]} -gt 0 ]; do
    left=()
    for f in "${todo[@]}"; do
        extra=()
        # ifort's -assume bscc ('\t' is a tab) and its widthless formats '(i)', '(l)'
        [ "$f" = m_readline.f90 ] && extra=(-fbackslash -fdec-format-defaults)
        if gfortran "${FFLAGS[@]}" "${extra[@]}" -c "$SRC/$f" -o "$OBJ/${f%.f90}.o" \
            2>"$OBJ/${f%.f90}.log"; then
            objs+=("$OBJ/${f%.f90}.o")
        else
            left+=("$f")
        fi
    done
    if [ ${#left[@]} -eq ${#todo[@]} ]; then
        echo "$0: these do not compile (see $OBJ/*.log): ${left[*]}" >&2
        exit 1
    fi
    todo=("${left[@]}")
done
echo "compiled ${#objs[@]} modules"

# the library (contact_addon.f90 exports cntc_* by bind(c) names) and the stand-alone program,
# which has no use for the library's m_caddon_data
gfortran "${FFLAGS[@]}" -shared "$SRC/contact_addon.f90" "${objs[@]}" "${LIBS[@]}" \
    -o "$PREFIX/bin/contact_addon_linux64.so"
exe_objs=()
for o in "${objs[@]}"; do [ "${o##*/}" = m_caddon_data.o ] || exe_objs+=("$o"); done
gfortran "${FFLAGS[@]}" "$SRC/contact.f90" "${exe_objs[@]}" "${LIBS[@]}" \
    -o "$PREFIX/bin/contact_linux64"

rm -rf "$PREFIX/python_intfc"
cp -r "$1/python_intfc" "$PREFIX/python_intfc"
# the commit built, for the provenance tools/contact_reference.py records (CONTACT_COMMIT
# overrides, for a source folder that is not a git checkout)
echo "${CONTACT_COMMIT:-$(git -C "$1" rev-parse HEAD 2>/dev/null || echo unknown)}" \
    > "$PREFIX/contact_commit.txt"
echo "built $PREFIX/bin/contact_addon_linux64.so and $PREFIX/bin/contact_linux64"
echo "export CONTACT_DIR=$PREFIX"
