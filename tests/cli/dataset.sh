# Sourced by the CLI test scripts that need ../shared/datasets; resolves it as the C++ tests do.
#   source "$(dirname "$0")/dataset.sh" "$source_dir"   → $data: SLAMKIT_DATA (default
#       ../shared/datasets), a relative path taken relative to the source tree
#   require_data SUBDIR   → skip (exit 77) when $data/SUBDIR is missing; under CI=true a missing
#       folder is a failure (exit 1), never a skip
data=${SLAMKIT_DATA:-../shared/datasets}
[[ $data == /* ]] || data="$1/$data"
require_data() {
  [[ -d "$data/$1" ]] && return 0
  if [[ ${CI:-} == true ]]; then echo "FAIL: datasets missing under CI=true: $data/$1"; exit 1; fi
  echo "SKIPPED: datasets not found: $data/$1 (set SLAMKIT_DATA)"; exit 77
}
