#!/usr/bin/env bash
# The models of a capture sequence (configs/sequences/*.yaml), comma-separated: its object,
# then each of its `others` (a list [a, b] or one number). Usage: sequence-models.sh FILE DATA
set -euo pipefail
file=$1 data=$2
models="capture:$file?data=$data"
for k in $(sed -n 's/^others: *\[\{0,1\}\([0-9, ]*\)\]\{0,1\} *\(#.*\)\{0,1\}$/\1/p' "$file" | tr ',' ' '); do
  models="$models,capture:$file?data=$data&object=$k"
done
echo "$models"
