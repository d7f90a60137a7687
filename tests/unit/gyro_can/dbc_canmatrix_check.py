"""The DBC read by a tool nobody here wrote (Debian's python3-canmatrix), against the golden frames
golden_frames.py writes from the README: every golden frame is found in the DBC by its message id
(the node bits cleared), has the DBC's length, and decodes with its Crc signal equal to its last
byte; the Parameter command and its Ack decode to the fields the README gives them.

Exit 0 when all hold, 1 with what did not, 77 (ctest: skipped) when canmatrix is missing and the
run is not strict (CI=true or HRGBENCH_STRICT=1 make it a failure)."""
import os
import pathlib
import runpy
import sys
import io
import contextlib

strict = os.environ.get("CI") == "true" or os.environ.get("HRGBENCH_STRICT") == "1"
try:
    with contextlib.redirect_stderr(io.StringIO()):  # it says which optional formats it lacks
        import canmatrix
        import canmatrix.formats
except ImportError:
    print("dbc_canmatrix_check: python3-canmatrix is missing (scripts/setup-debian.sh installs it)")
    sys.exit(1 if strict else 77)

here = pathlib.Path(__file__).resolve().parent
dbc_path = here.parents[2] / "drivers" / "gyro_can" / "hrg_gyro_v2.dbc"
with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
    db = list(canmatrix.formats.loadp(str(dbc_path)).values())[0]
out = io.StringIO()
with contextlib.redirect_stdout(out):
    runpy.run_path(str(here / "golden_frames.py"))

failures = []
decoded = {}
frames = 0
for line in out.getvalue().splitlines():
    name, text = line.split(" ", 1)
    if "#" not in text:
        continue  # the parameter block's words, not a frame
    ident, payload = text.split("##1") if "##1" in text else text.split("#")
    ident = int(ident, 16)
    data = bytes.fromhex(payload)
    frame = db.frame_by_id(canmatrix.ArbitrationId(ident & ~0xF))
    if frame is None:
        failures.append(f"{name}: no message 0x{ident & ~0xF:03X} in the DBC")
        continue
    if frame.size != len(data):
        failures.append(f"{name}: {len(data)} bytes, the DBC's {frame.name} has {frame.size}")
        continue
    signals = {k: v.raw_value for k, v in frame.decode(data).items()}
    if signals.get("Crc") != data[-1]:
        failures.append(f"{name}: Crc signal {signals.get('Crc')} != last byte {data[-1]}")
    decoded[name] = (frame.name, signals)
    frames += 1

expect = {
    "par_write6": ("CmdParameter", {"Token": 0x0D, "Op": 2, "WordIndex": 17, "Value": 0xBEEF}),
    "par_begin0": ("CmdParameter", {"Op": 1, "Value": 48, "Reserved": 0}),
    "ack_par_read0": ("Ack", {"Command": 0x45, "Mode": 1, "Arg": (17 << 16) | 0xBEEF}),
    "ack_cfg0": ("Ack", {"Command": 0x40, "Arg": 1000}),
    "cfg0wa": ("CmdConfigure", {"RunMode": 1, "SampleRate": 1000, "Reserved": 0}),
    "op4": ("OperatingSample", {"Seq": 0x2A, "AngleOutput": -3 * 2**21, "WaveAngle": 32768}),
    "loopsA3": ("OperatingLoopsA", {"Seq": 0x2A, "EnergyError": round(2e-4 * 2**28),
                                    "QuadratureRatio": round(-3e-7 * 2**34)}),
    "loopsB3": ("OperatingLoopsB", {"Seq": 0x2A, "AmplitudeEffort": round(1e-3 * 2**26),
                                    "QuadratureEffort": round(-1.5e-4 * 2**26)}),
    "loopsA0sat": ("OperatingLoopsA", {"Seq": 0xFF, "EnergyError": (1 << 23) - 1,
                                       "QuadratureRatio": -(1 << 23)}),
}
for name, (message, fields) in expect.items():
    if name not in decoded:
        failures.append(f"{name}: not among the golden frames")
        continue
    got_message, signals = decoded[name]
    if got_message != message:
        failures.append(f"{name}: decoded as {got_message}, expected {message}")
    for field, value in fields.items():
        if signals.get(field) != value:
            failures.append(f"{name}: {field} = {signals.get(field)}, expected {value}")

if failures:
    print("dbc_canmatrix_check: FAIL\n  " + "\n  ".join(failures))
    sys.exit(1)
print(f"dbc_canmatrix_check: {frames} golden frames decoded by canmatrix, every check held")
