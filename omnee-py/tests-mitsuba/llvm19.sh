# Sourced by ci.sh here and examples/mitsuba/run.sh: an LLVM that Dr.Jit's
# LLVM backend can use. Debian 12's LLVM 15 cannot compile volpath's kernels
# ("Cannot select: ... fminimum"); Debian's libllvm19 can. Installs it if
# missing and exports DRJIT_LIBLLVM_PATH.
llvm=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
if [ ! -e "$llvm" ]; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends libllvm19 >/dev/null
fi
export DRJIT_LIBLLVM_PATH="$llvm"
