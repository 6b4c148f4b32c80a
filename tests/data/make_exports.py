"""Write the tricky export files of ``tests/data/exports`` (run from anywhere; deterministic).

Each file holds one kind of trouble met in real historian and spreadsheet exports; the
expected reading of each is asserted in ``tests/test_read_loops.py``. Values follow
``pv = 50 + 0.5 k``, ``op = 30 + k``, ``sp = 50`` for row ``k`` unless a file says otherwise,
so a test can tell which row was kept. Run ``python tests/data/make_exports.py`` after
changing it, and commit the files.
"""

from __future__ import annotations

import shutil
from datetime import datetime, timedelta
from pathlib import Path

OUT = Path(__file__).resolve().parent / "exports"
START = datetime(2024, 10, 17, 21, 55, 0)
N = 12


def pv(k):
    return 50 + 0.5 * k


def op(k):
    return 30.0 + k


def stamp(seconds, fmt="%Y-%m-%d %H:%M:%S"):
    return (START + timedelta(seconds=seconds)).strftime(fmt)


def historian(tag, rows, time_format="yyyy-MM-dd HH:mm:ss", trailing=""):
    """PROCESSDATA export: five header lines, then tab-separated rows."""
    head = (
        f"PROCESSDATA\t{tag} Data\t{time_format}\r\n"
        f"8\t10\t{stamp(0)}\t{len(rows)}\r\n"
        f"tagname\t{tag}.MV\t{tag}.PV\t{tag}.SV\t{tag}.MODE\tbOpOFL\tbPvOFL\tbSpOFL\tbAutOFL\r\n"
        "desc\t流量_OP\t流量_PV\t流量_SP\tAut\tbOpOFL\tbPvOFL\tbSpOFL\tbAutOFL\r\n"
        "fsMax=3.19\tfsMin=0\tfsGridNum=10\tfdMax=3.19\tfdMin=0\tfdGridNum=10\tL=24\r\n"
    )
    body = "".join("\t".join(map(str, r)) + "\t0\t0\t0\t0" + trailing + "\r\n" for r in rows)
    return head + body


def write(name, text, encoding="utf-8"):
    path = OUT / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(text.encode(encoding))


def main():
    if OUT.exists():
        shutil.rmtree(OUT)
    OUT.mkdir()
    base = [(stamp(10 * k), op(k), pv(k), 50, 1) for k in range(N)]

    # Historian: a duplicated timestamp (row 4 written twice, the second with other values).
    rows = base[:5] + [(base[4][0], 99.0, 99.0, 50, 1)] + base[5:]
    write("historian_duplicate.txt", historian("2111FIC10201", rows), "gb18030")
    # Historian: status text in place of values.
    rows = [list(r) for r in base]
    for k, text in ((2, "Bad"), (3, "I/O Timeout"), (5, "Shutdown"), (7, "#VALUE!")):
        rows[k][2] = text
    rows[8][1] = "Calc Failed"
    write("historian_status.txt", historian("2411LIC30102", rows))
    # Historian: every row ends with an extra tab (pandas warned "loss of data").
    write("historian_trailing_tab.txt", historian("2111PIC23001", base, trailing="\t"))
    # Historian: milliseconds in the time stamps, sampled every 0.5 s.
    rows = [(stamp(0.5 * k, "%Y-%m-%d %H:%M:%S.%f")[:-3], op(k), pv(k), 50, 1) for k in range(N)]
    write("historian_ms.txt", historian("2411PDIC10321", rows, "yyyy-MM-dd HH:mm:ss.SSS"))

    lines = ["time,PV,OP,SP"] + [f"{10 * k},{pv(k)},{op(k)},50" for k in range(N)]
    # Rows out of time order (rows 3 and 7 swapped).
    shuffled = lines[:]
    shuffled[4], shuffled[8] = shuffled[8], shuffled[4]
    write("unsorted.csv", "\n".join(shuffled) + "\n")
    # Jittered sampling around 10 s, then a 40-s hole in the records.
    t = [0, 9, 20, 29, 40, 50, 60, 71, 80, 90, 100, 110, 150, 160, 170]
    write("irregular.csv", "time,PV,OP\n" + "".join(f"{s},{s / 10},{op(0)}\n" for s in t))
    # Blank rows (two inside the data, one at the end).
    blank = lines[:4] + [""] + lines[4:8] + [",,,"] + lines[8:] + [""]
    write("blank_rows.csv", "\n".join(blank) + "\n")
    # Comment and title lines before the header, CRLF line ends.
    text = "# exported from PI ProcessBook\r\n# tag FIC300\r\nUnit 3 loops\r\n"
    write("comments.csv", text + "\r\n".join(lines).replace("PV,OP", "FIC300.PV,FIC300.OP"))
    # European: ';' separator, decimal comma, day-first dates; latin-1 with a comment column.
    rows = [
        f"{stamp(5 * k, '%d.%m.%Y %H:%M:%S')};{str(pv(k)).replace('.', ',')};"
        f"{str(op(k) + 0.25).replace('.', ',')};50,0;Störung {k}°C"
        for k in range(N)
    ]
    write("european_latin1.csv", "Zeitstempel;TIC7.PV;TIC7.OP;TIC7.SP;Bemerkung\n".replace(
        "Zeitstempel", "Timestamp") + "\n".join(rows) + "\n", "latin-1")
    # UTF-16 with BOM, tab-separated (Excel's "Unicode text").
    text = "Time\tLIC5.PV\tLIC5.OP\n" + "".join(
        f"{stamp(60 * k)}\t{pv(k)}\t{op(k)}\n" for k in range(N)
    )
    write("unicode_text.txt", text, "utf-16")
    # Epoch milliseconds, epoch seconds and Excel serial days as time.
    t0_ms = 1_729_202_100_000  # 2024-10-17 21:55:00 UTC
    write("epoch_ms.csv", "timestamp,PV,OP\n" + "".join(
        f"{t0_ms + 250 * k},{pv(k)},{op(k)}\n" for k in range(N)))
    write("epoch_s.csv", "timestamp,PV,OP\n" + "".join(
        f"{t0_ms // 1000 + 2 * k},{pv(k)},{op(k)}\n" for k in range(N)))
    serial0 = 45582 + (21 * 3600 + 55 * 60) / 86400  # 2024-10-17 21:55:00
    write("excel_serial.csv", "Date,PV,OP\n" + "".join(
        f"{serial0 + 10 * k / 86400:.10f},{pv(k)},{op(k)}\n" for k in range(N)))
    # Several loops in one file, two naming styles.
    write("wide_two_loops.csv", "Timestamp,FIC1.PV,FIC1.OP,FIC1.SP,LIC2.MV,LIC2.PV,LIC2.SV\n"
          + "".join(f"{stamp(1 * k)},{pv(k)},{op(k)},50,{70 - k},{20 + k},20\n"
                    for k in range(N)))
    # Separate date and time-of-day columns, then a units row under the header.
    write("date_and_time.csv", "Date,Time,PV,OP\n" + "".join(
        f"{stamp(k, '%Y-%m-%d')},{stamp(30 * k, '%H:%M:%S')},{pv(k)},{op(k)}\n"
        for k in range(N)))
    write("units_row.csv", "time;PV;OP\ns;m3/h;%\n" + "".join(
        f"{k};{pv(k)};{op(k)}\n" for k in range(N)))
    # A sub-folder, and the folder index that describes files rather than holding a loop.
    write("site_b/FIC900.csv", "\n".join(lines) + "\n")
    write("index.csv", "file,label\nunsorted.csv,no_stiction\n")

    # Files that cannot be read, each for a reason a person can act on.
    write("no_time.csv", "PV,OP\n" + "".join(f"{pv(k)},{op(k)}\n" for k in range(N)))
    write("empty.csv", "")
    write("legacy.dat", "\n".join(lines) + "\n")
    write("old_workbook.xls", "not really an old workbook")
    write("broken.xlsx", "a text file named like a workbook")
    write("no_pv.csv", "time,OP,SP\n0,1,2\n10,3,4\n")

    # Optional formats, when their libraries are installed.
    try:
        import pandas as pd

        frame = pd.DataFrame({
            "Time": [START + timedelta(seconds=10 * k) for k in range(N)],
            "FIC8.PV": [pv(k) if k != 4 else "Bad" for k in range(N)],
            "FIC8.OP": [op(k) for k in range(N)],
            "FIC8.SP": [50.0] * N,
        })  # fmt: skip
        with pd.ExcelWriter(OUT / "workbook.xlsx", engine="openpyxl") as writer:
            title = pd.DataFrame([["Loop report FIC8"], [None]])
            title.to_excel(writer, sheet_name="data", header=False, index=False)
            frame.to_excel(writer, sheet_name="data", startrow=2, index=False)
        frame["FIC8.PV"] = [pv(k) for k in range(N)]
        frame.to_parquet(OUT / "table.parquet", index=False)
    except ImportError as exc:
        print(f"skipped .xlsx/.parquet: {exc}")


if __name__ == "__main__":
    main()
    print(f"wrote {sum(1 for p in OUT.rglob('*') if p.is_file())} files to {OUT}")
