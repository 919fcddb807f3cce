#!/usr/bin/env python3
"""CTest canopen.eds_to_cpp: tools/eds-to-cpp compiles config/swum.eds, and refuses broken copies
of it (what a real CANopen master trips on, and what would make the compiled table wrong) with
exit status 1 and one line naming the section and key, writing no output.
Usage: eds_to_cpp_test.py EDS_TO_CPP SWUM_EDS"""
import os
import re
import subprocess
import sys
import tempfile


def edit(text, section, key, value):
    """`text` with `key` of [section] set to `value` (None: the line removed)."""
    lines, current, done = [], None, False
    for line in text.splitlines():
        stripped = line.strip()
        if stripped.startswith("["):
            current = stripped[1:-1]
        elif current == section and stripped.split("=", 1)[0] == key:
            done = True
            if value is None:
                continue
            line = f"{key}={value}"
        lines.append(line)
    if not done:
        raise AssertionError(f"the EDS has no [{section}] {key} to change")
    return "\n".join(lines) + "\n"


def rename_section(text, old, new):
    if f"[{old}]\n" not in text:
        raise AssertionError(f"the EDS has no [{old}]")
    return text.replace(f"[{old}]\n", f"[{new}]\n")


# (what is broken, section, key, new value or None to remove the line, the error expected)
EDITS = [
    ("unknown DataType", "6040", "DataType", "0x0010", r"\[6040\] DataType: unknown data type 0x0010"),
    ("missing ParameterName", "1018sub2", "ParameterName", None, r"\[1018sub2\] ParameterName: missing"),
    ("number without 0x", "1018sub1", "DataType", "0007", r"\[1018sub1\] DataType: '0007' is not a number"),
    ("octal-looking VendorNumber", "DeviceInfo", "VendorNumber", "001",
     r"\[DeviceInfo\] VendorNumber: '001' is not a number"),
    ("ProductNumber unlike 0x1018", "DeviceInfo", "ProductNumber", "0x1",
     r"\[DeviceInfo\] ProductNumber: 0x1, but \[1018sub2\] DefaultValue is 0x5357554D"),
    ("NrOfRXPDO unlike the objects", "DeviceInfo", "NrOfRXPDO", "5", r"\[DeviceInfo\] NrOfRXPDO: 5"),
    ("limit outside the type", "6060", "HighLimit", "300", r"\[6060\] HighLimit: 300 is outside integer8 \(-128\.\.127\)"),
    ("one limit only", "60FF", "LowLimit", None, r"\[60FF\] LowLimit: missing"),
    ("limits the wrong way round", "2031", "LowLimit", "4000", r"\[2031\] LowLimit: 4000 is above HighLimit 3000"),
    ("default outside the limits", "60FF", "DefaultValue", "2000000",
     r"\[60FF\] DefaultValue: 2000000 is outside its limits \(-1000000\.\.1000000\)"),
    ("default outside the type", "1001", "DefaultValue", "0x100", r"\[1001\] DefaultValue: 256 is outside unsigned8"),
    ("node-relative default outside the type", "1800sub2", "DefaultValue", "$NODEID+0xFF",
     r"\[1800sub2\] DefaultValue: 256 is outside unsigned8"),
    ("unknown AccessType", "6040", "AccessType", "readwrite", r"\[6040\] AccessType: 'readwrite'"),
    ("PDOMapping on a string", "1008", "PDOMapping", "1", r"\[1008\] PDOMapping: 1 on an object no PDO"),
    ("PDOMapping neither 0 nor 1", "6040", "PDOMapping", "yes", r"\[6040\] PDOMapping: 'yes'"),
    ("SubNumber unlike the sections", "1018", "SubNumber", "0x6", r"\[1018\] SubNumber: 6, but 5 sub-index sections"),
    ("a sub-index that is no VAR", "1018sub1", "ObjectType", "0x8", r"\[1018sub1\] ObjectType: 0x8"),
    ("highest sub-index unlike the sections", "1018sub0", "DefaultValue", "0x3",
     r"\[1018sub0\] DefaultValue: 3, but the highest sub-index is 4"),
    ("count unlike the entries", "OptionalObjects", "SupportedObjects", "41",
     r"\[OptionalObjects\] SupportedObjects: 41, but the list has 42 entries \(1\.\.42\)"),
    ("manufacturer object in the wrong list", "OptionalObjects", "1", "0x2001",
     r"\[OptionalObjects\] 1: 0x2001 belongs in ManufacturerObjects"),
    ("mandatory object not listed", "MandatoryObjects", "3", "0x1005", r"\[MandatoryObjects\]: 0x1018 is mandatory"),
    ("non-ASCII name", "606C", "ParameterName", "Velocity actual value (\u00b5m/s)",
     r"\[606C\] ParameterName: only printable ASCII"),
]
# (what is broken, text appended to the EDS, the error expected)
APPENDS = [
    ("section in no list", "[6071]\nParameterName=Target torque\nObjectType=0x7\nDataType=0x0003\nAccessType=rw\n"
     "DefaultValue=0\nPDOMapping=1\n", r"\[6071\]: in no object list"),
    ("sub-index of no object", "[6072sub0]\nParameterName=x\n", r"\[6072sub0\]: a sub-index of 0x6072"),
    ("section twice", "[1000]\nParameterName=again\n", r"\[1000\]: defined twice"),
]


def cases(eds):
    for name, section, key, value, expected in EDITS:
        yield name, edit(eds, section, key, value), expected
    for name, text, expected in APPENDS:
        yield name, eds + "\n" + text, expected
    yield "listed object without a section", rename_section(eds, "2052", "2053"), \
        r"\[ManufacturerObjects\] \d+: 0x2052 has no section \[2052\]"


def run(tool, eds_text, folder):
    eds = os.path.join(folder, "swum.eds")
    out = os.path.join(folder, "out.cpp")
    if os.path.exists(out):
        os.remove(out)
    with open(eds, "w", encoding="utf-8") as f:
        f.write(eds_text)
    result = subprocess.run([sys.executable, tool, eds, out], capture_output=True, text=True, timeout=30)
    return result, out


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    tool, source = sys.argv[1], sys.argv[2]
    with open(source, encoding="ascii") as f:
        eds = f.read()
    failures = 0
    with tempfile.TemporaryDirectory() as folder:
        result, out = run(tool, eds, folder)
        if result.returncode != 0 or result.stderr:
            print(f"FAIL the project's EDS: exit {result.returncode}: {result.stderr.strip()}")
            failures += 1
        else:
            with open(out, encoding="ascii") as f:
                generated = f.read()
            for expected in ('{0x1000, 0x00, "Device type", DataType::unsigned32, Access::ro, false, 131474LL',
                             '{0x1800, 0x01, "COB-ID used by TPDO", DataType::unsigned32, Access::rw, false, 384LL, true',
                             '{0x60FF, 0x00, "Target velocity (um/s)", DataType::integer32, Access::rw, true, 0LL, '
                             'false, nullptr, true, -1000000LL, 1000000LL}',
                             'DataType::visible_string, Access::const_, false, 0LL, false, '
                             '"swum-emu bimodal standing-wave ultrasonic motor drive"'):
                if expected not in generated:
                    print(f"FAIL the generated table lacks: {expected}")
                    failures += 1
        count = 0
        for name, text, pattern in cases(eds):
            count += 1
            result, out = run(tool, text, folder)
            lines = result.stderr.strip().splitlines()
            if result.returncode != 1 or len(lines) != 1 or not re.search(pattern, lines[0]) or os.path.exists(out):
                print(f"FAIL {name}: exit {result.returncode}, output written: {os.path.exists(out)}, "
                      f"stderr: {result.stderr.strip()!r}, expected /{pattern}/")
                failures += 1
            else:
                print(f"ok   {name}: {lines[0]}")
    print(f"eds_to_cpp_test: {count} broken copies, {failures} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
