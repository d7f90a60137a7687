#!/usr/bin/env bash
# README command 1: install what is missing (Debian packages), build, run the main job.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/setup-debian.sh"
bash "$root/scripts/build.sh"
bash "$root/scripts/main-job.sh"
