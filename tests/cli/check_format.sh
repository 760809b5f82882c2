#!/bin/sh
# Fails, naming the lines, when a C++ source of the project differs from what clang-format makes of it
# with the repository's .clang-format (written with Debian's clang-format 14; another version may
# disagree on a few lines). Usage: check_format.sh CLANG_FORMAT SOURCE_ROOT
set -eu
fmt="$1"
cd "$2"
find core constraints elements input drivers tests bench examples \( -name '*.cpp' -o -name '*.hpp' \) -print \
  | sort | xargs "$fmt" --dry-run --Werror
