#!/usr/bin/env bash
# Renders the example reports as a customer receives them: runs the acceptance test
# (passed and failed) and the spindle run-in against the simulated drive, then prints each
# HTML report to PDF with headless Chromium and each PDF page to PNG (pdftoppm, from
# poppler-utils) for looking at. Usage: tests/render_reports.sh [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-target/rendered-reports}"
mkdir -p "$out"
chromium="$(command -v chromium || command -v chromium-browser || command -v google-chrome || true)"
if [ -z "$chromium" ]; then
  echo "no chromium: apt-get install -y chromium" >&2
  exit 2
fi
cargo build --quiet
bin=target/debug/drivescript
"$bin" run recipes/acceptance-test.yaml --fast --output-dir "$out" --report acceptance.html --junit acceptance.xml >/dev/null
"$bin" run recipes/acceptance-test.yaml --fast --set tolerance=0.0001% --output-dir "$out" \
    --report acceptance-failed.html >/dev/null || true
"$bin" run recipes/spindle-run-in.yaml --fast --output-dir "$out" --report run-in.html >/dev/null
for name in acceptance acceptance-failed run-in; do
  "$chromium" --headless --no-sandbox --disable-gpu --no-pdf-header-footer \
      --print-to-pdf="$out/$name.pdf" "$out/$name.html" 2>/dev/null
  if command -v pdftoppm >/dev/null; then
    pdftoppm -r 60 -png "$out/$name.pdf" "$out/$name-page"
  fi
  echo "$out/$name.pdf"
done
