"""``frustum records``: list the catalog, show or plot a record (catalog id or file)."""

import json
import math

from pipeline.errors import InputError

__all__ = ["register", "add_record_options", "load_record", "record_inputs", "record_source"]


def register(subparsers):
    """Add the ``records`` command group to the ``frustum`` parser."""
    parser = subparsers.add_parser("records", help="ground-motion records: list, show, plot")
    sub = parser.add_subparsers(dest="records_command", metavar="ACTION")
    parser.set_defaults(handler=lambda args: (parser.print_help(), 2)[1])

    p_list = sub.add_parser("list", help="record sets and ids of records/catalog.toml")
    p_list.add_argument("--set", dest="set_id", help="list the records of one set")
    p_list.set_defaults(handler=_list)

    for name, helptext in (("show", "metadata and intensity measures"),
                           ("plot", "figure of histories and spectrum (.png, .pdf, .svg, ...)")):
        p = sub.add_parser(name, help=helptext)
        p.add_argument("record", metavar="ID_OR_FILE",
                       help="catalog id (e.g. FEMA-FF-01), a record file, or 2-3 files X,Y[,Z] (e.g. an AT2 pair)")
        add_record_options(p)
        if name == "show":
            p.add_argument("--json", action="store_true", help="one JSON object per component (JSON lines)")
            p.set_defaults(handler=_show)
        else:
            p.add_argument("--out", required=True,
                           help="figure file to write, any format matplotlib writes: .png, .pdf, .svg, ...")
            p.set_defaults(handler=_plot)


def add_record_options(parser):
    """The options that say how to read a record file (shared by ``simulate`` and ``records show|plot``)."""
    parser.add_argument("--units", help="units of files without calibration (MiniSEED, SAC, text): "
                        "m/s2, cm/s2 (gal), mm/s2, g")
    parser.add_argument("--components", metavar="X,Y[,Z]",
                        help="channel codes or trace ids of x, y[, z], e.g. HNE,HNN,HNZ (y may be 'none': y = 0)")
    parser.add_argument("--missing-y", choices=("error", "zero"), default="error",
                        help="a record with one horizontal component: fail (default) or set y = 0 "
                        "(the single trace of a file is then x)")
    parser.add_argument("--dt", type=float, metavar="S",
                        help="time step [s] of a text file without a time column (e.g. an OpenSees input)")
    parser.add_argument("--baseline", choices=("demean", "linear"),
                        help="remove the mean or a linear trend from every component before use (baseline_correct)")


def record_source(text):
    """A ``--record`` value: a catalog id or file, or ``X,Y[,Z]`` naming 2 or 3 files."""
    from pathlib import Path

    if "," in text and not Path(text).exists():
        parts = [p.strip() for p in text.split(",")]
        if not 2 <= len(parts) <= 3 or not all(parts):
            raise InputError(f"--record {text!r}: give one id or file, or 2 or 3 files X,Y[,Z] separated by commas")
        return parts
    return text


def record_inputs(record):
    """[(what, path)] of the record files a ``--record`` value names (none for a catalog id), for output checks."""
    import os

    if not record:
        return []
    source = record_source(record)
    return [("record file", p) for p in ([source] if isinstance(source, str) else source) if os.path.exists(p)]


def load_record(args):
    """The record named by ``args.record`` read with the options of :func:`add_record_options`.

    The options that say how to read a file (``--units``, ``--components``,
    ``--dt``) are refused on a catalog id rather than ignored.
    """
    from pathlib import Path

    from pipeline.groundmotion import load

    if args.dt is not None and not (math.isfinite(args.dt) and args.dt > 0):
        raise InputError(f"--dt {args.dt!r}: give the time step as a positive number of seconds")
    source = record_source(args.record)
    if isinstance(source, str) and not Path(source).exists():
        from pipeline.groundmotion import catalog

        given = [f"--{name.replace('_', '-')}" for name in ("units", "components", "dt")
                 if getattr(args, name, None) is not None]
        if given and source in catalog.catalog().get("records", {}):  # the catalog states these; never ignored
            raise InputError(f"{' '.join(given)}: {source} is a catalog record, read in the units, components and "
                             f"sampling records/catalog.toml gives it; drop {', '.join(given)} (for record files only)")
    components = None
    if args.components:
        components = [c if c.lower() != "none" else None for c in args.components.split(",")]
    processing = [{"step": "baseline", "type": args.baseline}] if args.baseline else None
    return load(source, units=args.units, components=components, missing_y=args.missing_y,
                dt=args.dt, processing=processing)


def _list(args):
    from pipeline.groundmotion import catalog

    if args.set_id:
        for rid in catalog.list_records(args.set_id):
            e = catalog.entry(rid)
            label = e.get("description") or ", ".join(str(e[k]) for k in ("event", "year", "station") if k in e)
            print(f"{rid:18s} {label}")
        return 0
    for s in catalog.list_sets():
        print(f"{s['id']:14s} {s['n_records']:3d} records  {s['title']}")
        print(f"{'':14s} source: {s['source']}; format: {s['format']}; licence: {s['licence']}")
    print("\n`frustum records list --set ID` lists a set's record ids.")
    return 0


def _component_summary(gm, name):
    from pipeline.groundmotion import intensity as im

    a, dt = gm.component(name), gm.dt
    d595, _, _ = im.significant_duration(a, dt)
    return {
        "record_id": gm.record_id,
        "component": name,
        "npts": gm.npts,
        "dt": dt,
        "duration": gm.duration,
        "pga": im.pga(a),
        "pgv": im.pgv(a, dt),
        "pgd": im.pgd(a, dt),
        "arias": im.arias_intensity(a, dt),
        "cav": im.cav(a, dt),
        "d5_95": d595,
        "sa_0.2s": im.spectral_acceleration(a, dt, 0.2),
        "sa_1.0s": im.spectral_acceleration(a, dt, 1.0),
    }


def _show(args):
    gm = load_record(args)
    rows = [_component_summary(gm, c) for c in gm.components]
    if args.json:
        for row in rows:
            print(json.dumps(row, allow_nan=False))
        return 0
    print(f"{gm.record_id}: {gm.npts} samples, dt = {gm.dt:g} s, duration {gm.duration:g} s, components {', '.join(gm.components)}")
    for k, v in gm.metadata.items():
        if k != "parameters":
            print(f"  {k}: {v}")
    units = {"pga": "m/s^2", "pgv": "m/s", "pgd": "m", "arias": "m/s", "cav": "m/s", "d5_95": "s",
             "sa_0.2s": "m/s^2", "sa_1.0s": "m/s^2"}
    print(f"  {'measure':18s}" + "".join(f"{c:>12s}" for c in gm.components))
    for key, unit in units.items():
        print(f"  {key + ' [' + unit + ']':18s}" + "".join(f"{row[key]:12.4g}" for row in rows))
    from pipeline.groundmotion import intensity as im

    print(f"  RotD50 PGA {im.rotd50(gm.acc_x, gm.acc_y, gm.dt):.4g} m/s^2, RotD100 PGA {im.rotd100(gm.acc_x, gm.acc_y, gm.dt):.4g} m/s^2")
    for name, tr in zip(gm.components, gm.stream):
        print(f"  processing of {name} ({tr.id}):")
        for line in tr.stats.get("processing", []):
            print(f"    {line}")
    return 0


def _plot(args):
    from pipeline.groundmotion.plot import plot_motion
    from pipeline.paths import check_plot_file

    check_plot_file(args.out, "--out", inputs=record_inputs(args.record))  # before loading the record
    gm = load_record(args)
    plot_motion(gm, args.out)
    print(f"wrote {args.out}")
    return 0
