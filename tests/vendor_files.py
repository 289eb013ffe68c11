"""Files as real acquisition software writes them, for tests of the readers and the commands.

Each builder writes one file into a given folder and returns a :class:`VendorFile`: the path,
the channel map (TOML text) a user would write to read it, and ``facts`` (what the file holds:
rates, start times, the quirk it reproduces, the error a reader should give). The layouts were
checked against public descriptions of each tool's output (named in each docstring); where no
public description was found, the docstring says so and what the layout is modelled on.

Signals come from a :class:`rollerrig.recordings.recording.Recording` in SI units (canonical
channel names): :func:`bench_recording` (closed-form, cheap: constant speed, motor line, an
extra unexplained line, noise) or :func:`adhesion_recording` (a short adhesion test on the
digital twin, :func:`rollerrig.recordings.synthetic.synthetic_recording`, plus an extra
unexplained 37 Hz line). Builders convert to the units the tool would store (N.m, bar, 1/min,
mm, V) and the channel maps convert back, so a read-back can be compared with the source.
"""

from __future__ import annotations

import datetime as _dt
import functools
import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from rollerrig.recordings.recording import CANONICAL_CHANNELS, Recording

__all__ = [
    "ADHESION_PROTOCOL",
    "EXTRA_LINE_HZ",
    "VendorFile",
    "adhesion_recording",
    "bench_recording",
    "canape_ascii_csv",
    "canedge_can_mdf",
    "catman_ascii",
    "daqmx_multitask_tdms",
    "german_bench_csv",
    "inca_canape_mdf",
    "labview_lvm",
    "labview_waveform_tdms",
    "matlab_struct_mat",
    "picoscope_csv",
    "twincat_scope_csv",
    "without_file_section",
]

EXTRA_LINE_HZ = 37.0
"""Frequency of the extra unexplained line in the torque [Hz] (a pump or fan on a real rig)."""

START = np.datetime64("2024-08-05T11:46:13.250000")
"""Default absolute start of a recording (UTC; 13:46:13 local summer time in Central Europe)."""

# SI unit -> (unit the tools store, factor from SI to that unit)
_TORQUE = ("Nm", 1.0)
_PRESSURE = ("bar", 1e-5)
_SPEED = ("1/min", 60.0 / (2.0 * math.pi))
_DISPLACEMENT = ("mm", 1e3)
_COUNTS = ("counts", 1.0)
_MAP_UNITS = {"Nm": "N.m", "1/min": "rpm", "counts": "1"}
"""Vendor unit -> the spelling a user writes in the channel map."""


class VendorFile(NamedTuple):
    """A file written like a vendor tool writes it.

    Attributes
    ----------
    path : Path
        The file.
    channel_map : str
        Channel map (TOML text) that reads it: canonical names, units, ``[file]`` dialect keys.
    facts : dict
        What the file holds (``tool``, ``quirks``, rates [Hz], channel names, ``expect_error``
        for files no reader can turn into a recording, ...).
    """

    path: Path
    channel_map: str
    facts: dict[str, Any]

    def write_map(self, path: str | Path | None = None) -> Path:
        """Write :attr:`channel_map` to ``path`` (default: ``<file stem>.map.toml`` beside it)."""
        target = (
            Path(path) if path is not None else self.path.with_name(self.path.stem + ".map.toml")
        )
        target.write_text(self.channel_map, encoding="utf-8")
        return target


def without_file_section(channel_map: str) -> str:
    """The channel map without its ``[file]`` table (everything left to the reader's sniffing)."""
    out, skipping = [], False
    for line in channel_map.splitlines():
        stripped = line.strip()
        if stripped.startswith("["):
            skipping = stripped == "[file]"
        if not skipping:
            out.append(line)
    return "\n".join(out) + "\n"


# ---------------------------------------------------------------------------------------------
# Signal sources


def _injected(what: str, frequency: float, amplitude: float) -> dict[str, Any]:
    """A hand-injected line, in the structure of ``DisturbanceModel.injected_lines``."""
    return {
        "what": what,
        "frequency [Hz]": float(frequency),
        "amplitude [N.m]": float(amplitude),
        "channel": "torque",
    }


def _injected_note(line: Mapping[str, Any]) -> str:
    return (
        f"test fixture: a line at {line['frequency [Hz]']:g} Hz, {line['amplitude [N.m]']:g} N.m "
        f"on {line['channel']} was INJECTED by hand ({line['what']}); it is not a finding"
    )


def _rig_constants() -> dict[str, float]:
    from rollerrig.rig.parameters import default_rig

    rig = default_rig()
    return {
        "roller_radius": rig.geometry.roller_radius_x,
        "wheel_radius": rig.geometry.wheel_radius_x,
        "cpr": float(rig.sensors.encoder_counts_per_revolution),
        "area": float(rig.sensors.air_spring_effective_area),
    }


def bench_recording(
    duration_s: float = 2.0,
    sample_rate: float = 250.0,
    *,
    speed_kmh: float = 30.0,
    torque_Nm: float = 150.0,
    load_N: float = 4300.0,
    extra_line_Hz: float | None = EXTRA_LINE_HZ,
    extra_line_Nm: float = 3.0,
    seed: int = 0,
) -> Recording:
    """A closed-form recording at constant speed (no simulation): what a rig logs while rolling.

    Torque [N.m] = ``torque_Nm`` + the induction motor's line (5 pole pairs x roller rotation,
    3 N.m) + the extra line (``extra_line_Hz``, ``extra_line_Nm``) + white noise (1 N.m); wheel
    and roller speeds [rad/s] and exact cumulative encoder counts (10000 per revolution); the
    air-spring pressure [Pa] giving ``load_N`` on the rig's effective area, with noise; the laser
    displacement at the torque sensor [m] (60 µm run-out at the roller rotation).

    Parameters
    ----------
    duration_s : float
        Length [s].
    sample_rate : float
        Rate [Hz].
    speed_kmh : float
        Rolling speed [km/h] (wheel and roller at the same peripheral speed, 0.5 % creep).
    torque_Nm : float
        Mean roller-shaft torque [N.m].
    load_N : float
        Normal load [N].
    extra_line_Hz, extra_line_Nm : float
        The extra speed-independent line [Hz] and its amplitude [N.m]; None: no line.
    seed : int
        Seed of the noise.
    """
    k = _rig_constants()
    n = round(duration_s * sample_rate)
    t = np.arange(n) / sample_rate
    v = speed_kmh / 3.6
    omega_r = v / k["roller_radius"]
    omega_w = 1.005 * v / k["wheel_radius"]
    rng = np.random.default_rng(seed)
    f_am = 5 * omega_r / (2 * math.pi)
    torque = torque_Nm + 3.0 * np.sin(2 * math.pi * f_am * t + 0.3) + rng.standard_normal(n)
    injected = [_injected("induction-motor line (closed form)", f_am, 3.0)]
    if extra_line_Hz is not None:
        torque = torque + extra_line_Nm * np.sin(2 * math.pi * extra_line_Hz * t + 1.1)
        injected.append(_injected("extra unexplained line", extra_line_Hz, extra_line_Nm))
    channels = {
        "torque": torque,
        "wheel_speed": np.full(n, omega_w),
        "roller_speed": np.full(n, omega_r),
        "wheel_encoder_counts": np.floor(omega_w * t * k["cpr"] / (2 * math.pi) + 1e-6),
        "roller_encoder_counts": np.floor(omega_r * t * k["cpr"] / (2 * math.pi) + 1e-6),
        "air_spring_pressure": load_N / k["area"] + 100.0 * rng.standard_normal(n),
        "displacement_torque_sensor": 6e-5 * np.sin(omega_r * t + 0.7)
        + 1e-6 * rng.standard_normal(n),
    }
    units = {name: CANONICAL_CHANNELS[name][0] for name in channels}
    meta = {
        "source": "tests/vendor_files.py:bench_recording",
        "injected_lines": injected,
        "notes": [_injected_note(line) for line in injected],
    }
    return Recording(t, channels, units, meta)


ADHESION_PROTOCOL = """
[experiment]
name = "vendor-adhesion-30kmh"
description = "Short adhesion test: roll, ramp to 600 N.m, hold, release, rest (vendor fixtures)."
normal_load_kN = 4.3
friction = "dry"
roller_speed_kmh = 30.0

[[step]]
action = "hold"
duration_s = 2.0

[[step]]
action = "ramp_torque"
to_Nm = 600.0
duration_s = 2.0

[[step]]
action = "hold"
duration_s = 0.5

[[step]]
action = "release_torque"
duration_s = 0.02

[[step]]
action = "hold"
duration_s = 3.0
"""
"""The twin protocol behind :func:`adhesion_recording` (7.5 s)."""


@functools.cache
def adhesion_recording(
    extra_line_Hz: float | None = EXTRA_LINE_HZ, extra_line_Nm: float = 4.0, seed: int = 1
) -> tuple[Recording, Any]:
    """A short adhesion test recorded at 250 Hz, with an extra unexplained line in the torque.

    The twin (:data:`ADHESION_PROTOCOL`, the bundled rig, the reference Radau solver at 500 Hz:
    about 2 s, no compilation) is recorded by
    :func:`rollerrig.recordings.synthetic.synthetic_recording` with its default disturbances; the
    wheel and roller speeds [rad/s] of the twin are added (a speed sensor, as INCA/CANape and
    catman files carry) and a line at ``extra_line_Hz`` [Hz] of ``extra_line_Nm`` [N.m] is
    added to the torque (a pump on the rig: explained by nothing the toolkit knows). Cached.

    Returns
    -------
    recording : Recording
        Its metadata lists the line in ``injected_lines`` and says so in ``notes`` (the files
        the builders write carry the signals only, as a real file would).
    truth : xarray.Dataset
        The twin's truth on the recording's time axis.
    """
    from rollerrig.experiment.protocol import protocol_from_toml_string
    from rollerrig.recordings.synthetic import synthetic_recording
    from rollerrig.rig.parameters import default_rig
    from rollerrig.solve.simulation import Simulation

    protocol = protocol_from_toml_string(ADHESION_PROTOCOL)
    ds = Simulation(default_rig(), protocol, output_rate=500.0, solver="reference").run()
    rec, truth = synthetic_recording(ds, sample_rate=250.0, seed=seed)
    t = rec.time
    torque = np.array(rec["torque"])
    extra = []
    if extra_line_Hz is not None:
        torque += extra_line_Nm * np.sin(2 * math.pi * extra_line_Hz * (t - t[0]) + 0.4)
        extra.append(_injected("extra unexplained line", extra_line_Hz, extra_line_Nm))
    wheel = "wheel_speed" if "wheel_speed" in truth else "wheel_disc_speed"
    channels = dict(rec.channels)
    channels.update(
        torque=torque,
        wheel_speed=np.asarray(truth[wheel].values, dtype=float),
        roller_speed=np.asarray(truth["roller_speed"].values, dtype=float),
    )
    units = {name: CANONICAL_CHANNELS[name][0] for name in channels}
    meta = dict(rec.metadata)
    meta["injected_lines"] = [*meta.get("injected_lines", []), *extra]
    meta["notes"] = [*meta.get("notes", []), *(_injected_note(line) for line in extra)]
    return Recording(t, channels, units, meta), truth


# ---------------------------------------------------------------------------------------------
# helpers


def _toml_str(text: str) -> str:
    return json.dumps(text, ensure_ascii=False)  # a TOML basic string is a JSON string


def _map_text(
    description: str,
    columns: Mapping[str, tuple[str, str]],
    *,
    time: Mapping[str, Any] | None = None,
    file: Mapping[str, Any] | None = None,
    extra: Mapping[str, tuple[str, str]] | None = None,
) -> str:
    """Channel map TOML: ``columns`` is canonical name -> (file column, unit)."""

    def value(v: Any) -> str:
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return _toml_str(v)
        return repr(v)

    lines = [f"description = {_toml_str(description)}", ""]
    if file:
        lines.append("[file]")
        lines += [f"{k} = {value(v)}" for k, v in file.items()]
        lines.append("")
    if time:
        lines.append("[time]")
        lines += [f"{k} = {value(v)}" for k, v in time.items()]
        lines.append("")
    for table, entries in (("channels", columns), ("extra", extra or {})):
        for name, (column, unit) in entries.items():
            lines += [f"[{table}.{name}]", f"column = {_toml_str(column)}"]
            lines += [f"unit = {_toml_str(unit)}", ""]
    return "\n".join(lines)


def _vendor(rec: Recording, name: str, unit: tuple[str, float]) -> np.ndarray:
    return np.asarray(rec[name], dtype=float) * unit[1]


_STANDARD = (  # canonical channel -> (vendor unit, factor), in the order tools list them
    ("torque", _TORQUE),
    ("wheel_speed", _SPEED),
    ("roller_speed", _SPEED),
    ("wheel_encoder_counts", _COUNTS),
    ("roller_encoder_counts", _COUNTS),
    ("air_spring_pressure", _PRESSURE),
    ("displacement_torque_sensor", _DISPLACEMENT),
)


def _present(rec: Recording, names: Mapping[str, str]) -> list[tuple[str, str, tuple[str, float]]]:
    """(canonical, vendor column, (unit, factor)) for the channels of ``rec`` named in ``names``."""
    return [(c, names[c], u) for c, u in _STANDARD if c in names and c in rec]


def _fmt(values: np.ndarray, decimals: int, decimal: str = ".") -> list[str]:
    text = [f"{v:.{decimals}f}" for v in values]
    return [s.replace(".", decimal) for s in text] if decimal != "." else text


def _local(t0: np.datetime64, offset_s: float) -> _dt.datetime:
    """Local wall-clock time (CEST, UTC+2) of ``t0 + offset_s`` as a naive datetime."""
    utc = t0.astype("datetime64[us]").astype(_dt.datetime)
    return utc + _dt.timedelta(hours=2, seconds=float(offset_s))


# ---------------------------------------------------------------------------------------------
# NI TDMS


def labview_waveform_tdms(
    folder: str | Path,
    rec: Recording | None = None,
    *,
    name: str = "labview-waveform.tdms",
    start: np.datetime64 = START,
    segments: int = 4,
) -> VendorFile:
    """LabVIEW "Write to TDMS" of waveform data (LabVIEW 2019-2023, TDMS file format 2.0).

    Reproduces what LabVIEW stores when a waveform array is wired to Write to TDMS: one group
    ("Adhesion test"), channels named as the waveform attribute ``NI_ChannelName`` (with spaces),
    float64 samples without a time channel, and the standard waveform properties on every
    channel: ``wf_start_time`` (a TDMS timestamp, UTC), ``wf_increment`` [s], ``wf_start_offset``
    (0.0), ``wf_samples``, ``wf_xname`` = "Time", ``wf_xunit_string`` = "s", plus
    ``unit_string`` and ``NI_UnitDescription``; the file object carries ``name``, ``title``,
    ``author``, ``datetime`` and the group a ``description``. The data arrive in ``segments``
    TDMS segments (one per loop iteration of the acquisition VI), the properties only in the
    first, as LabVIEW appends.

    Sources: NI, "TDMS File Format Internal Structure" (predefined waveform properties);
    hampel-soft DokuWiki "TDMS" (the wf_* names, which are required, ``wf_start_time``
    optional; ``NI_ChannelName``; ``unit_string``); npTDMS reading docs (timestamps as
    ``numpy.datetime64``).

    Map: torque, encoder counts, air-spring pressure [bar], laser [mm] as ``"Group/Channel"``;
    no ``[time]``: time comes from the waveform properties.
    """
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    rec = rec if rec is not None else bench_recording()
    path = Path(folder) / name
    group = "Adhesion test"
    names = {
        "torque": "Torque T56",
        "wheel_encoder_counts": "Wheel encoder",
        "roller_encoder_counts": "Roller encoder",
        "air_spring_pressure": "Air spring",
        "displacement_torque_sensor": "Laser 3",
    }
    present = _present(rec, names)
    dt = float(np.median(np.diff(rec.time)))
    n = rec.time.size
    props_common = {
        "wf_start_time": start,
        "wf_start_offset": 0.0,
        "wf_increment": dt,
        "wf_samples": n,
        "wf_xname": "Time",
        "wf_xunit_string": "s",
    }
    bounds = np.linspace(0, n, max(1, segments) + 1).astype(int)
    with TdmsWriter(str(path)) as writer:
        for k in range(len(bounds) - 1):
            a, b = bounds[k], bounds[k + 1]
            objects = []
            if k == 0:
                objects.append(
                    RootObject(
                        {
                            "name": path.stem,
                            "title": "Adhesion test 30 km/h dry",
                            "author": "rig operator",
                            "datetime": start,
                        }
                    )
                )
                objects.append(GroupObject(group, {"description": f"NI USB-6341, {1.0 / dt:g} Hz"}))
            for canonical, column, (unit, factor) in present:
                data = np.asarray(rec[canonical], dtype=float)[a:b] * factor
                props = (
                    {
                        **props_common,
                        "unit_string": unit,
                        "NI_UnitDescription": unit,
                        "NI_ChannelName": column,
                    }
                    if k == 0
                    else {}
                )
                objects.append(ChannelObject(group, column, data, properties=props))
            writer.write_segment(objects)
    cmap = _map_text(
        "LabVIEW waveform TDMS (Write to TDMS); time from wf_increment / wf_start_time",
        {c: (f"{group}/{col}", _MAP_UNITS.get(u, u)) for c, col, (u, _) in present},
    )
    facts = {
        "tool": "LabVIEW Write to TDMS (waveform)",
        "group": group,
        "channels": {c: f"{group}/{col}" for c, col, _ in present},
        "sample_rate_Hz": 1.0 / dt,
        "n_samples": n,
        "start": str(start),
        "segments": len(bounds) - 1,
        "quirks": ["no time channel", "properties only in the first segment", "spaces in names"],
    }
    return VendorFile(path, cmap, facts)


def daqmx_multitask_tdms(
    folder: str | Path,
    *,
    name: str = "daqmx-two-tasks.tdms",
    duration_s: float = 2.0,
    fast_rate_Hz: float = 19200.0,
    slow_rate_Hz: float = 10.0,
    slow_start_delay_s: float = 0.35,
    slow_samples: int | None = None,
    start: np.datetime64 = START,
    extra_line_Hz: float = EXTRA_LINE_HZ,
    seed: int = 0,
) -> VendorFile:
    """NI-DAQmx TDMS logging of two tasks into one file (DAQmx 19-21 "Log and Read").

    Reproduces DAQmx logging: one group per task, named after the task; channels named after
    the virtual channel, with ``NI_ChannelName`` the physical channel (``cDAQ1Mod1/ai0``); raw
    int16 ADC codes stored unscaled with the scale in the properties (``NI_Scaling_Status`` =
    "unscaled", ``NI_Number_Of_Scales``, ``NI_Scale[0]_Scale_Type`` = "Linear", slope,
    intercept) so that the reader must apply it; ``unit_string`` / ``NI_UnitDescription``; the
    waveform properties with ``wf_samples`` = 1 (what DAQmx writes, not the channel length).

    Task "TorqueLaser" at ``fast_rate_Hz`` (the HBM QuantumX / NI 9237 rate of the seed's
    torque and laser measurements, 19.2 kHz): torque [Nm] with a line at ``extra_line_Hz`` and
    the laser at the torque sensor [mm]. Task "AirSpring" at ``slow_rate_Hz`` (10 Hz):
    air-spring pressure [bar], started ``slow_start_delay_s`` later (its own ``wf_start_time``).
    ``slow_samples`` forces the slow task's length (e.g. equal to the fast task's, the trap of
    index alignment).

    Source: the channel properties of a DAQmx-logged file as npTDMS lists them (a public
    example script printing ``NI_Scaling_Status: unscaled``, ``NI_Number_Of_Scales``,
    ``NI_Scale[1]_Linear_Slope``, ``NI_ChannelName: Dev1/ai0``, ``unit_string: Volts``,
    ``wf_start_time``, ``wf_increment``, ``wf_start_offset: 0.0``, ``wf_samples: 1``); npTDMS's
    scaling code (``Linear`` scales applied when the status is not "scaled"). DAQmx writes its
    own raw-data index (DAQmx scalers), which npTDMS cannot write: here the scale is a property
    scale of a plain int16 channel, which readers apply the same way.
    """
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    path = Path(folder) / name
    fast = bench_recording(
        duration_s, fast_rate_Hz, extra_line_Hz=extra_line_Hz, extra_line_Nm=3.0, seed=seed
    )
    n_slow = slow_samples if slow_samples is not None else round(duration_s * slow_rate_Hz)
    t_slow = slow_start_delay_s + np.arange(n_slow) / slow_rate_Hz
    rng = np.random.default_rng(seed + 1)
    k = _rig_constants()
    pressure_bar = (4300.0 / k["area"]) * 1e-5 + 0.002 * rng.standard_normal(n_slow)

    def int16_scaled(values: np.ndarray, full_scale: float) -> tuple[np.ndarray, dict[str, Any]]:
        slope = full_scale / 32767.0
        codes = np.clip(np.round(values / slope), -32768, 32767).astype(np.int16)
        return codes, {
            "NI_Scaling_Status": "unscaled",
            "NI_Number_Of_Scales": 1,
            "NI_Scale[0]_Scale_Type": "Linear",
            "NI_Scale[0]_Linear_Slope": slope,
            "NI_Scale[0]_Linear_Y_Intercept": 0.0,
            "NI_Scale[0]_Linear_Input_Source": 0xFFFFFFFF,
        }

    def wf(rate: float, start_time: np.datetime64) -> dict[str, Any]:
        return {
            "wf_start_time": start_time,
            "wf_start_offset": 0.0,
            "wf_increment": 1.0 / rate,
            "wf_samples": 1,
        }

    slow_start = start + np.timedelta64(round(slow_start_delay_s * 1e6), "us")
    torque_codes, torque_scale = int16_scaled(fast["torque"], 3000.0)
    laser_codes, laser_scale = int16_scaled(fast["displacement_torque_sensor"] * 1e3, 5.0)
    pressure_codes, pressure_scale = int16_scaled(pressure_bar, 10.0)

    def channel(group, chan, codes, scale, unit, phys, rate, start_time):
        props = {
            **scale,
            "NI_ChannelName": phys,
            "unit_string": unit,
            "NI_UnitDescription": unit,
            **wf(rate, start_time),
        }
        return ChannelObject(group, chan, codes, properties=props)

    with TdmsWriter(str(path)) as writer:
        writer.write_segment(
            [
                RootObject({"name": path.stem, "DAQmx_Version": "21.3"}),
                GroupObject("TorqueLaser", {}),
                channel(
                    "TorqueLaser",
                    "Torque",
                    torque_codes,
                    torque_scale,
                    "Nm",
                    "cDAQ1Mod1/ai0",
                    fast_rate_Hz,
                    start,
                ),
                channel(
                    "TorqueLaser",
                    "Laser TS",
                    laser_codes,
                    laser_scale,
                    "mm",
                    "cDAQ1Mod1/ai1",
                    fast_rate_Hz,
                    start,
                ),
                GroupObject("AirSpring", {}),
                channel(
                    "AirSpring",
                    "Pressure",
                    pressure_codes,
                    pressure_scale,
                    "bar",
                    "cDAQ1Mod2/ai0",
                    slow_rate_Hz,
                    slow_start,
                ),
            ]
        )
    cmap = _map_text(
        "NI-DAQmx logging, two tasks (19.2 kHz torque/laser, 10 Hz air spring)",
        {
            "torque": ("TorqueLaser/Torque", "N.m"),
            "displacement_torque_sensor": ("TorqueLaser/Laser TS", "mm"),
            "air_spring_pressure": ("AirSpring/Pressure", "bar"),
        },
    )
    facts = {
        "tool": "NI-DAQmx TDMS logging (two tasks)",
        "fast_rate_Hz": fast_rate_Hz,
        "slow_rate_Hz": slow_rate_Hz,
        "slow_start_delay_s": slow_start_delay_s,
        "n_fast": fast.time.size,
        "n_slow": n_slow,
        "slow_time_s": t_slow,
        "slow_pressure_Pa": np.asarray(pressure_codes, dtype=float)
        * pressure_scale["NI_Scale[0]_Linear_Slope"]
        * 1e5,
        "source": fast,
        "quirks": [
            "raw int16 with property scales",
            "wf_samples = 1",
            "tasks with different rates and start times",
        ],
    }
    return VendorFile(path, cmap, facts)


# ---------------------------------------------------------------------------------------------
# ASAM MDF 4


def _raster_name(rate: float) -> str:
    ms = 1000.0 / rate
    return f"{ms:g}ms"


def inca_canape_mdf(
    folder: str | Path,
    rec: Recording | None = None,
    *,
    name: str = "inca-canape.mf4",
    slow_rate_Hz: float = 10.0,
    tool: str = "CANape",
) -> VendorFile:
    """An ETAS INCA 7 / Vector CANape 14-21 measurement: MDF 4.10, one data group per raster.

    Reproduces: one channel group per acquisition raster, each with its own master channel
    named ``time``; the acquisition name of each group is the raster ("100ms", "4ms",
    "Trigger") and its comment names the source (as XCP/CCP rasters appear in CANape, or as
    INCA's device rasters); the same channel name in two groups at different rates ("Torque"
    in the slow raster, first in the file, and in the fast raster); rasters starting at
    slightly different times; a group with no samples (an event raster that never fired); the
    header's author/department/project/subject and a file history naming the tool (Vector
    Informatik GmbH, CANape 14.0.20.2386, as the MATLAB "Access MDF-Files" example shows for
    CANapeBasic.MF4).

    Groups: 0 "100ms" (``slow_rate_Hz``): "Torque" [Nm] (a slow monitor copy) and
    "p_Luftfeder" [bar]; 1 "<fast>ms" (the rate of ``rec``): "Torque" [Nm], "n_Rad", "n_Rolle"
    [1/min], "Laser_TS" [mm]; 2 "Trigger": "Trig_Flag" with 0 samples.

    Sources: asammdf 8 API (``MDF.append(..., acq_name=, comment=)``, one master "time" per
    group); MathWorks "Access MDF-Files" and ``mdfChannelGroupInfo`` (AcquisitionName and
    Comment of channel groups in CANape/INCA files); issue 7 (duplicated names silently taken
    from data group 0).

    Map: ``"<fast raster>/Torque"`` (group acquisition name) for the torque; the rest by name.
    ``facts["torque_by_index"]`` gives the same entry by group index (``"1/Torque"``).
    """
    from asammdf import MDF, Signal
    from asammdf.blocks.v4_blocks import FileHistory

    rec = rec if rec is not None else bench_recording(2.0, 1000.0)
    path = Path(folder) / name
    fs = rec.sample_rate
    fast_name, slow_name = _raster_name(fs), _raster_name(slow_rate_Hz)
    step = max(1, round(fs / slow_rate_Hz))
    t = rec.time - rec.time[0]
    mdf = MDF(version="4.10")
    mdf.header.author = "rig operator"
    mdf.header.department = "Rail vehicle test rigs"
    mdf.header.project = "Wheel-roller adhesion"
    mdf.header.subject = "Roller rig"
    history = FileHistory()
    history.comment = (
        "<FHcomment><TX>created</TX><tool_id>"
        + tool
        + "</tool_id><tool_vendor>"
        + ("Vector Informatik GmbH" if tool == "CANape" else "ETAS GmbH")
        + "</tool_vendor><tool_version>"
        + ("14.0.20.2386" if tool == "CANape" else "7.4.0")
        + "</tool_version>"
        "<user_name>rig</user_name></FHcomment>"
    )
    mdf.file_history.append(history)
    # group 0: slow raster (listed first, as in the file of issue 7), starts 50 ms late
    ts = t[::step] + 0.05
    keep = ts <= t[-1]
    slow = [
        Signal(
            _vendor(rec, "torque", _TORQUE)[::step][keep],
            ts[keep],
            name="Torque",
            unit="Nm",
            comment="torque, slow monitor copy",
        )
    ]
    if "air_spring_pressure" in rec:
        slow.append(
            Signal(
                _vendor(rec, "air_spring_pressure", _PRESSURE)[::step][keep],
                ts[keep],
                name="p_Luftfeder",
                unit="bar",
            )
        )
    mdf.append(slow, acq_name=slow_name, comment=f"XCP: {slow_name} raster")
    # group 1: fast raster
    tf = t + 0.0004
    fast = [
        Signal(
            _vendor(rec, "torque", _TORQUE),
            tf,
            name="Torque",
            unit="Nm",
            comment="roller shaft torque T56",
        )
    ]
    for canonical, column in (("wheel_speed", "n_Rad"), ("roller_speed", "n_Rolle")):
        if canonical in rec:
            fast.append(Signal(_vendor(rec, canonical, _SPEED), tf, name=column, unit="1/min"))
    if "displacement_torque_sensor" in rec:
        fast.append(
            Signal(
                _vendor(rec, "displacement_torque_sensor", _DISPLACEMENT),
                tf,
                name="Laser_TS",
                unit="mm",
            )
        )
    mdf.append(fast, acq_name=fast_name, comment=f"XCP: {fast_name} raster")
    # group 2: an event raster that never fired
    mdf.append(
        [Signal(np.array([], dtype=float), np.array([], dtype=float), name="Trig_Flag", unit="")],
        acq_name="Trigger",
        comment="event raster (no samples)",
    )
    mdf.save(str(path), overwrite=True)
    mdf.close()
    columns = {"torque": (f"{fast_name}/Torque", "N.m")}
    if "wheel_speed" in rec:
        columns["wheel_speed"] = ("n_Rad", "rpm")
    if "roller_speed" in rec:
        columns["roller_speed"] = ("n_Rolle", "rpm")
    if "air_spring_pressure" in rec:
        columns["air_spring_pressure"] = ("p_Luftfeder", "bar")
    if "displacement_torque_sensor" in rec:
        columns["displacement_torque_sensor"] = ("Laser_TS", "mm")
    cmap = _map_text(f"{tool} MDF4, one data group per raster (masters all named 'time')", columns)
    facts = {
        "tool": f"{tool} / INCA MDF 4.10",
        "groups": {0: slow_name, 1: fast_name, 2: "Trigger"},
        "fast_rate_Hz": fs,
        "slow_rate_Hz": fs / step,
        "torque_by_index": "1/Torque",
        "torque_by_name": f"{fast_name}/Torque",
        "empty_channel": "Trig_Flag",
        "source": rec,
        "quirks": [
            "every master named 'time'",
            "Torque in two groups at different rates",
            "an empty group",
            "rasters start at different times",
        ],
    }
    return VendorFile(path, cmap, facts)


def canedge_can_mdf(
    folder: str | Path, *, name: str = "canedge-raw-can.mf4", n_frames: int = 300
) -> VendorFile:
    """A CSS Electronics CANedge2 log (firmware 01.07): MDF 4.11 with raw CAN frames only.

    Reproduces ASAM MDF 4 bus logging as CAN loggers write it: a channel group with the bus
    event flag whose structure channel ``CAN_DataFrame`` has the members ``BusChannel``,
    ``ID``, ``IDE``, ``DLC``, ``DataLength``, ``DataBytes``, ``Dir``, ``EDL``, ``BRS``,
    ``ESI``, with a CAN bus source; the physical signals (torque, speeds) exist only inside the
    8-byte payloads and need a DBC file to decode. Frames every 10 ms with ID 0x123 (torque as
    int16 x 0.1 N.m, little-endian) and 0x124 (roller speed).

    Source: the ``MF4Writer`` of python-can (``can/io/mf4.py``: the STD_DTYPE structure and the
    ``SourceInformation(source_type=SOURCE_BUS, bus_type=BUS_TYPE_CAN)`` acquisition source),
    which follows the ASAM MDF bus logging standard used by CANedge and Vector loggers.

    ``facts["expect_error"]``: the reader should stop with one error saying the file holds raw
    CAN frames and must be decoded with a DBC first (e.g. ``asammdf``'s
    ``MDF.extract_bus_logging``).
    """
    from asammdf import MDF, Signal
    from asammdf.blocks.v4_blocks import SourceInformation
    from asammdf.blocks.v4_constants import BUS_TYPE_CAN, SOURCE_BUS

    path = Path(folder) / name
    dtype = np.dtype(
        [
            ("CAN_DataFrame.BusChannel", "<u1"),
            ("CAN_DataFrame.ID", "<u4"),
            ("CAN_DataFrame.IDE", "<u1"),
            ("CAN_DataFrame.DLC", "<u1"),
            ("CAN_DataFrame.DataLength", "<u1"),
            ("CAN_DataFrame.DataBytes", "(64,)u1"),
            ("CAN_DataFrame.Dir", "<u1"),
            ("CAN_DataFrame.EDL", "<u1"),
            ("CAN_DataFrame.BRS", "<u1"),
            ("CAN_DataFrame.ESI", "<u1"),
        ]
    )
    frames = np.zeros(n_frames, dtype=dtype)
    t = 0.005 * np.arange(n_frames)
    ids = np.where(np.arange(n_frames) % 2 == 0, 0x123, 0x124)
    torque_raw = np.round((150.0 + 3.0 * np.sin(2 * math.pi * 14.7 * t)) * 10).astype("<i2")
    frames["CAN_DataFrame.BusChannel"] = 1
    frames["CAN_DataFrame.ID"] = ids
    frames["CAN_DataFrame.DLC"] = 8
    frames["CAN_DataFrame.DataLength"] = 8
    payload = np.zeros((n_frames, 8), dtype=np.uint8)
    payload[:, 0:2] = torque_raw.view(np.uint8).reshape(-1, 2)
    frames["CAN_DataFrame.DataBytes"][:, :8] = payload
    mdf = MDF(version="4.11")
    mdf.header.comment = (
        "<HDcomment><TX>CANedge2 log</TX><common_properties>"
        '<e name="device type">CANedge2</e><e name="firmware version">01.07.02</e>'
        "</common_properties></HDcomment>"
    )
    source = SourceInformation(source_type=SOURCE_BUS, bus_type=BUS_TYPE_CAN)
    mdf.append(Signal(frames, t, name="CAN_DataFrame", source=source), acq_name="CAN1")
    mdf.save(str(path), overwrite=True)
    mdf.close()
    cmap = _map_text(
        "CANedge raw CAN log: signals only after DBC decoding",
        {"torque": ("Torque", "N.m"), "roller_speed": ("n_Rolle", "rpm")},
    )
    facts = {
        "tool": "CANedge2 (ASAM MDF4 bus logging)",
        "expect_error": "raw CAN frames: decode with a DBC file first",
        "quirks": ["only CAN_DataFrame structure channels", "no physical channels"],
    }
    return VendorFile(path, cmap, facts)


# ---------------------------------------------------------------------------------------------
# Text exports


def picoscope_csv(
    folder: str | Path,
    rec: Recording | None = None,
    *,
    name: str = "picoscope.csv",
    pretrigger_s: float = 0.1,
    torque_Nm_per_V: float = 300.0,
    laser_mm_per_V: float = 1.0,
    blank_line: bool = True,
) -> VendorFile:
    """PicoScope 6 "Save As > CSV" of a two-channel capture.

    Reproduces: a header row ``Time,Channel A,Channel B``, a units row ``(ms),(V),(V)`` under
    it, an empty line before the numbers (files exported by PicoScope 6.x; the manual's example
    omits it: ``blank_line=False``), comma-separated, decimal point, UTF-8 with CRLF line ends,
    time in ms starting before the trigger (negative), channels in volts: A the torque
    amplifier output (``torque_Nm_per_V``), B the laser (``laser_mm_per_V``).

    Source: PicoScope 6 User's Guide (psw.en, 2007-2012), section 6.1.1.1.1 "Text formats"
    ("Time, Channel A, Channel B / (µs), (V), (V) / -500.004, 5.511, 1.215"; UTF-8 by
    default). Units row in ms here (the map's time units are s and ms).

    Map: ``[file]`` header_row 0, units_row 1, separator ",", decimal "."; ``[time]`` column
    "Time" in ms; torque and laser with ``scale`` (V -> N.m, V -> mm).
    """
    rec = rec if rec is not None else bench_recording()
    path = Path(folder) / name
    t_ms = (rec.time - rec.time[0] - pretrigger_s) * 1e3
    a = np.asarray(rec["torque"]) / torque_Nm_per_V
    cols = [_fmt(t_ms, 6), _fmt(a, 6)]
    header, units = ["Time", "Channel A"], ["(ms)", "(V)"]
    has_b = "displacement_torque_sensor" in rec
    if has_b:
        b = np.asarray(rec["displacement_torque_sensor"]) * 1e3 / laser_mm_per_V
        cols.append(_fmt(b, 6))
        header.append("Channel B")
        units.append("(V)")
    lines = [",".join(header), ",".join(units)]
    if blank_line:
        lines.append("")
    lines += [",".join(row) for row in zip(*cols, strict=True)]
    path.write_bytes(("\r\n".join(lines) + "\r\n").encode("utf-8"))
    text = [
        'description = "PicoScope 6 CSV export: A = torque amplifier [V], B = laser [V]"',
        "",
        "[file]",
        'separator = ","',
        'decimal = "."',
        "header_row = 0",
        "units_row = 1",
        "",
        "[time]",
        'column = "Time"',
        'unit = "ms"',
        "",
        "[channels.torque]",
        'column = "Channel A"',
        'unit = "N.m"',
        f"scale = {torque_Nm_per_V!r}",
        "",
    ]
    if has_b:
        text += [
            "[channels.displacement_torque_sensor]",
            'column = "Channel B"',
            'unit = "mm"',
            f"scale = {laser_mm_per_V!r}",
            "",
        ]
    facts = {
        "tool": "PicoScope 6 CSV",
        "sample_rate_Hz": rec.sample_rate,
        "t0_s": -pretrigger_s,
        "source": rec,
        "quirks": [
            "units row (ms),(V)",
            *(["blank line after the units row"] if blank_line else []),
            "negative pre-trigger time",
            "volts scaled by the map",
        ],
    }
    return VendorFile(path, "\n".join(text), facts)


def catman_ascii(
    folder: str | Path,
    rec: Recording | None = None,
    *,
    name: str = "catman-export.txt",
    start: np.datetime64 = START,
    time_column: str = "absolute",
) -> VendorFile:
    """HBM catman AP 5 "Export > ASCII" of a QuantumX measurement, German Windows settings.

    Reproduces: a preamble of ``key<TAB>value`` lines (source file, comment, export date), a
    blank line, then a tab-separated header row, a units row (``s``, ``N·m``, ``1/min``,
    ``bar``, ``mm``; the date column has none), decimal commas, Windows-1252/Latin-1 text with
    CRLF; the first column an absolute day-first timestamp ``05.08.2024 13:46:13,004`` (local
    time, milliseconds after a comma), the second catman's relative time channel
    ``Zeit  1 - Standardmessrate`` [s].

    Source: no public description of catman's ASCII export layout was found (HBM's catman FAQ
    pages do not show one); the layout follows issue 7's description of catman exports
    (preamble, tab, units row, day-first dates, decimal comma) and catman's naming of its time
    channels ("Time  1 - default sample rate" in the English UI).

    Map: ``[file]`` separator tab, decimal ",", header_row 5, units_row 6, encoding latin-1,
    dayfirst, ``date_format`` "%d.%m.%Y %H:%M:%S,%f"; ``[time]`` the absolute column
    (``time_column="absolute"``) or the relative one (``"relative"``, unit s).
    """
    rec = rec if rec is not None else bench_recording()
    path = Path(folder) / name
    names = {
        "torque": "Drehmoment T56",
        "wheel_speed": "Drehzahl Rad",
        "roller_speed": "Drehzahl Rolle",
        "air_spring_pressure": "Luftfederdruck",
        "displacement_torque_sensor": "Laser 3",
    }
    present = _present(rec, names)
    t = rec.time - rec.time[0]
    stamps = []
    for s in t:
        local = _local(start, s)
        stamps.append(local.strftime("%d.%m.%Y %H:%M:%S,") + f"{local.microsecond // 1000:03d}")
    rel = "Zeit  1 - Standardmessrate"
    unit_text = {"Nm": "N·m"}
    header = ["Datum/Uhrzeit", rel] + [col for _, col, _ in present]
    units = ["", "s"] + [unit_text.get(u, u) for _, _, (u, _) in present]
    cols = [stamps, _fmt(t, 6, ",")]
    cols += [_fmt(_vendor(rec, c, u), 6, ",") for c, _, u in present]
    preamble = [
        "Datei:\tC:\\Messdaten\\Haftversuch_30kmh_trocken.BIN",
        "Kommentar:\tHaftversuch 30 km/h trocken, 4,3 kN",
        "Exportiert mit:\tcatman AP 5.6",
        "Exportdatum:\t" + _local(start, 600.0).strftime("%d.%m.%Y %H:%M:%S"),
        "",
    ]
    lines = [*preamble, "\t".join(header), "\t".join(units)]
    lines += ["\t".join(row) for row in zip(*cols, strict=True)]
    path.write_bytes(("\r\n".join(lines) + "\r\n").encode("cp1252"))
    file = {
        "separator": "\t",
        "decimal": ",",
        "header_row": 5,
        "units_row": 6,
        "encoding": "latin-1",
        "dayfirst": True,
    }
    if time_column == "absolute":
        file["date_format"] = "%d.%m.%Y %H:%M:%S,%f"
        time = {"column": "Datum/Uhrzeit"}
    else:
        time = {"column": rel, "unit": "s"}
    cmap = _map_text(
        "HBM catman ASCII export (German settings)",
        {c: (col, _MAP_UNITS.get(u, u)) for c, col, (u, _) in present},
        time=time,
        file=file,
    )
    facts = {
        "tool": "HBM catman ASCII export",
        "sample_rate_Hz": rec.sample_rate,
        "start_local": stamps[0],
        "relative_time_column": rel,
        "source": rec,
        "quirks": [
            "preamble",
            "units row",
            "decimal comma",
            "day-first timestamps",
            "Latin-1",
            "N·m",
        ],
    }
    return VendorFile(path, cmap, facts)


def twincat_scope_csv(
    folder: str | Path,
    rec: Recording | None = None,
    *,
    name: str = "twincat-scope.csv",
    separator: str = "\t",
    decimal: str = ",",
    shared_time: bool = False,
    eof: bool = True,
    slow_every: int = 10,
    start: np.datetime64 = START,
) -> VendorFile:
    """TwinCAT 3 Scope View "Export > CSV" of a scope recording of the rig's PLC symbols.

    Reproduces: a file header of ``key<sep>value`` rows (``Name``, ``File``, ``Starttime of
    export`` / ``Endtime of export`` as a Windows FILETIME and the local date in German words),
    two blank lines; the channels' header, one row per property (``Name``, ``SymbolComment``,
    ``Data-Type``, ``SampleTime[ms]``, ..., ``Unit`` as ``Nm (Torque)``, ``Unit ScaleFactor``,
    ``Unit Offset``), a property's key above every time column; a blank line; the samples, the
    time columns in ms. By default each channel has its own time column; ``shared_time`` (the
    export's "exclude double timestamps") gives the channels of one sample time one. The air
    spring's pressure is sampled ``slow_every`` times slower and exported last, so the rows
    below its last sample are short; ``decimal`` the exporting PC's locale (``0,2``), ``eof``
    a last line ``EOF``; LF line ends, UTF-8.

    Source: the layout of TwinCAT Scope 3.4 exports (TwinCAT 3.1.4024) in the test data of
    pytcs (github.com/CagtayFabry/pytcs, tests/data: default, ExcludeDoubleTimestamp,
    Seperator and ContainEOF variants); the rows and keys here are written anew, no file of it
    is copied.

    Map: no ``[file]`` or ``[time]`` section (each channel's own time column); torque [N.m],
    speeds [rpm]. The pressure is not in the map: a channel of another rate the map leaves out.
    """
    rec = rec if rec is not None else bench_recording()
    path = Path(folder) / name
    names = {
        "torque": "fTorqueT56",
        "wheel_speed": "fSpeedWheel",
        "roller_speed": "fSpeedRoller",
        "air_spring_pressure": "fPressureAirSpring",
    }
    present = _present(rec, names)
    fast = [x for x in present if x[0] != "air_spring_pressure"]
    slow = [x for x in present if x[0] == "air_spring_pressure"]
    t_ms = (rec.time - rec.time[0]) * 1e3
    dt_ms = float(np.median(np.diff(t_ms)))
    unit_words = {"Nm": "Nm (Torque)", "1/min": "1/min (Rotational speed)", "bar": "bar (Pressure)"}
    symbols = {c: f"MAIN.fbRig.{col}" for c, col, _ in present}

    # groups: (sample time [ms], times [ms], [(canonical, column, unit)])
    groups = []
    if shared_time:
        groups.append((dt_ms, t_ms, fast))
    else:
        groups += [(dt_ms, t_ms, [x]) for x in fast]
    if slow:
        groups.append((dt_ms * slow_every, t_ms[::slow_every], slow))

    def num(v: float) -> str:
        text = f"{v:.6f}".rstrip("0").rstrip(".")
        return text.replace(".", decimal) if decimal != "." else text

    def row(key: str, value) -> list[str]:
        cells = []
        for sample_time, _, chans in groups:
            cells.append(key)
            cells += [value(c, col, u, sample_time) for c, col, u in chans]
        return cells

    properties = [
        ("SymbolComment", lambda *a: ""),
        ("Data-Type", lambda *a: "REAL64"),
        ("SampleTime[ms]", lambda c, col, u, st: num(st)),
        ("VariableSize", lambda *a: "8"),
        ("SymbolBased", lambda *a: "True"),
        ("IndexGroup", lambda *a: "16448"),
        ("IndexOffset", lambda *a: "385048"),
        ("SymbolName", lambda c, *a: symbols[c]),
        ("NetID", lambda *a: "5.42.118.20.1.1"),
        ("Port", lambda *a: "851"),
        ("Offset", lambda *a: "0"),
        ("ScaleFactor", lambda *a: "1"),
        ("BitMask", lambda *a: "0xffffffffffffffff"),
        ("Unit", lambda c, col, u, st: unit_words.get(u[0], u[0])),
        ("Unit ScaleFactor", lambda *a: "1"),
        ("Unit Offset", lambda *a: "0"),
    ]
    # FILETIME: 100 ns since 1601-01-01 UTC (beyond numpy's datetime64[ns] range: datetime)
    since = start.astype("datetime64[us]").astype(_dt.datetime) - _dt.datetime(1601, 1, 1)
    ticks = since // _dt.timedelta(microseconds=1) * 10
    end_ticks = ticks + round(float(t_ms[-1]) * 1e4)
    local = _local(start, 0.0)
    days = ["Montag", "Dienstag", "Mittwoch", "Donnerstag", "Freitag", "Samstag", "Sonntag"]
    months = ["Januar", "Februar", "März", "April", "Mai", "Juni", "Juli", "August",
              "September", "Oktober", "November", "Dezember"]  # fmt: skip
    words = f"{days[local.weekday()]}, {local.day}. {months[local.month - 1]} {local.year}"
    lines = [
        ["Name", "Haftversuch_30kmh"],
        ["File", "C:\\TwinCAT\\Scope\\Haftversuch_30kmh.svdx"],
        ["Starttime of export", str(ticks), words, local.strftime("%H:%M:%S.%f")[:-3]],
        ["Endtime of export", str(end_ticks), words, local.strftime("%H:%M:%S.%f")[:-3]],
        [],
        [],
        row("Name", lambda c, col, u, st: col),
        *[row(key, value) for key, value in properties],
        [],
    ]
    n_rows = len(t_ms)
    columns = []  # per group: (times, [values]) as text, padded with None past the end
    for _, times, chans in groups:
        columns.append((
            [num(v) for v in times],
            [[num(v) for v in _vendor(rec, c, u)[:: (slow_every if chans is slow else 1)]]
             for c, _, u in chans],
        ))  # fmt: skip
    for k in range(n_rows):
        cells: list[str] = []
        last_running = max(g for g, (times, _) in enumerate(columns) if k < len(times))
        for times, values in columns[: last_running + 1]:
            if k < len(times):
                cells += [times[k], *(v[k] for v in values)]
            else:  # a channel that ended, left of one still running: blank (a space) cells
                cells += [" "] * (1 + len(values))
        lines.append(cells)
    text = "\n".join(separator.join(c) for c in lines) + "\n"
    if eof:
        text += "EOF\n"
    path.write_bytes(text.encode("utf-8"))
    cmap = _map_text(
        "TwinCAT Scope CSV export",
        {c: (col, _MAP_UNITS.get(u, u)) for c, col, (u, _) in fast},
    )
    facts = {
        "tool": "TwinCAT 3 Scope View CSV export",
        "sample_rate_Hz": rec.sample_rate,
        "slow_channel": slow[0][1] if slow else None,
        "source": rec,
        "quirks": [
            "key-value file header",
            "a property row per key, a key above every time column",
            "time columns in ms",
            "ragged rows",
            "decimal comma" if decimal == "," else "decimal point",
            "EOF line" if eof else "no EOF line",
        ],
    }
    return VendorFile(path, cmap, facts)


def german_bench_csv(
    folder: str | Path,
    *,
    name: str = "pruefstand-langsam.csv",
    start_local: str = "12.08.24 23:58:30",
    duration_s: int = 180,
    seed: int = 0,
) -> VendorFile:
    """A German test-bench / NI DIAdem CSV export of slow channels at 1 Hz across midnight.

    Reproduces: ``;`` separators, decimal commas, a units row under the header, Latin-1 text
    (``°C``), absolute timestamps ``dd.mm.yy HH:MM:SS`` (day-first, two-digit year) as DIAdem's
    "DataFileSave" CSV and bench software with German regional settings write them; the record
    crosses midnight from day 12 to day 13, where a month-first reading jumps (12.08. read as
    8 December, 13.08. as 13 August: time runs backwards) and a per-row format guess switches
    format mid-file.

    Source: issue 7 (``05.08.24 13:46:13`` as catman/DIAdem/German benches write it; day
    12 -> 13 and midnight); Windows German regional format (``dd.MM.yy``, ``HH:mm:ss``,
    decimal comma, list separator ``;``).

    Map: ``[file]`` separator ";", decimal ",", header_row 0, units_row 1, encoding latin-1,
    dayfirst, date_format "%d.%m.%y %H:%M:%S"; ``[time]`` "Datum/Uhrzeit"; roller speed [1/min]
    and air-spring pressure [bar]; the temperature as an extra [°C] is not mapped.
    """
    path = Path(folder) / name
    t0 = _dt.datetime.strptime(start_local, "%d.%m.%y %H:%M:%S")
    rng = np.random.default_rng(seed)
    n = int(duration_s)
    speed = 352.1 + 0.4 * rng.standard_normal(n)  # 30 km/h on a 0.452 m roller: 352 1/min
    pressure = 0.860 + 0.002 * rng.standard_normal(n)
    temp = 31.5 + 0.01 * np.arange(n)
    lines = ["Datum/Uhrzeit;Drehzahl Rolle;Luftfederdruck;Temperatur Rolle", ";1/min;bar;°C"]
    for i in range(n):
        stamp = (t0 + _dt.timedelta(seconds=i)).strftime("%d.%m.%y %H:%M:%S")
        lines.append(
            ";".join(
                [
                    stamp,
                    f"{speed[i]:.1f}".replace(".", ","),
                    f"{pressure[i]:.3f}".replace(".", ","),
                    f"{temp[i]:.2f}".replace(".", ","),
                ]
            )
        )
    path.write_bytes(("\r\n".join(lines) + "\r\n").encode("latin-1"))
    cmap = _map_text(
        "German bench CSV (DIAdem style): ; and decimal comma, day-first dates",
        {
            "roller_speed": ("Drehzahl Rolle", "rpm"),
            "air_spring_pressure": ("Luftfederdruck", "bar"),
        },
        time={"column": "Datum/Uhrzeit"},
        file={
            "separator": ";",
            "decimal": ",",
            "header_row": 0,
            "units_row": 1,
            "encoding": "latin-1",
            "dayfirst": True,
            "date_format": "%d.%m.%y %H:%M:%S",
        },
    )
    facts = {
        "tool": "German bench / DIAdem CSV",
        "sample_rate_Hz": 1.0,
        "n_samples": n,
        "start_local": start_local,
        "roller_speed_rpm": speed,
        "pressure_bar": pressure,
        "crosses_midnight_at_sample": int(
            (24 * 3600 - (t0.hour * 3600 + t0.minute * 60 + t0.second)) % (24 * 3600)
        ),
        "quirks": [
            "day-first two-digit-year dates",
            "midnight and day 12 -> 13",
            "; and ,",
            "Latin-1 °C",
        ],
    }
    return VendorFile(path, cmap, facts)


def canape_ascii_csv(
    folder: str | Path, rec: Recording | None = None, *, name: str = "canape-export.csv"
) -> VendorFile:
    """A Vector CANape 14 measurement exported to ASCII/CSV (semicolon, units row).

    Reproduces: a header row of signal names starting with ``time``, a units row (``s``,
    ``Nm``, ``1/min``, ``bar``, ``mm``), ``;`` separators with a decimal point (CANape's
    default with German list separator), values in ``%.9g``-style scientific notation where
    small, all rasters already merged onto the fastest one.

    Source: no public description of CANape's CSV export was found; modelled on the common
    layout of measurement-tool CSV exports (names row, units row, ``;``) and on asammdf's CSV
    export of MDF files (a ``timestamps``/``time`` first column). Treat the exact spelling as an
    approximation; the properties tested (units row, ``;`` with decimal point) are what matters.

    Map: ``[file]`` separator ";", decimal ".", header_row 0, units_row 1; ``[time]`` "time" [s].
    """
    rec = rec if rec is not None else bench_recording()
    path = Path(folder) / name
    names = {
        "torque": "Torque",
        "wheel_speed": "n_Rad",
        "roller_speed": "n_Rolle",
        "air_spring_pressure": "p_Luftfeder",
        "displacement_torque_sensor": "Laser_TS",
    }
    present = _present(rec, names)
    t = rec.time - rec.time[0]
    header = ["time"] + [col for _, col, _ in present]
    units = ["s"] + [u for _, _, (u, _) in present]
    cols = [[f"{v:.6f}" for v in t]]
    cols += [[f"{v:.9g}" for v in _vendor(rec, c, u)] for c, _, u in present]
    lines = [";".join(header), ";".join(units)] + [";".join(r) for r in zip(*cols, strict=True)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    cmap = _map_text(
        "Vector CANape CSV export",
        {c: (col, _MAP_UNITS.get(u, u)) for c, col, (u, _) in present},
        time={"column": "time", "unit": "s"},
        file={"separator": ";", "decimal": ".", "header_row": 0, "units_row": 1},
    )
    facts = {
        "tool": "Vector CANape CSV export",
        "sample_rate_Hz": rec.sample_rate,
        "source": rec,
        "quirks": ["units row", "; with decimal point"],
    }
    return VendorFile(path, cmap, facts)


def labview_lvm(
    folder: str | Path,
    rec: Recording | None = None,
    *,
    name: str = "labview-measurement.lvm",
    start: np.datetime64 = START,
) -> VendorFile:
    """A LabVIEW Measurement File (.lvm, writer version 2) with two segments.

    Reproduces "Write To Measurement File" (LabVIEW 8.6 and later): the file header
    (``LabVIEW Measurement``, ``Writer_Version 2``, ``Reader_Version 2``, ``Separator Tab``,
    ``Decimal_Separator .``, ``Multi_Headings No``, ``X_Columns One``, ``Time_Pref Relative``,
    ``Operator``, ``Date``, ``Time``) ended by ``***End_of_Header***``; then one segment per
    call of the VI (here two halves of the recording), each with its own header (``Channels``,
    ``Samples``, ``Date``, ``Time``, ``X_Dimension``, ``X0``, ``Delta_X``) ended by
    ``***End_of_Header***``, a column header ``X_Value<TAB>names...<TAB>Comment`` and rows of
    tab-separated numbers with six decimals; CRLF line ends.

    Sources: NI, "Specification for the LabVIEW Measurement File (.lvm)" (file and segment
    headers, tags, ``***End_of_Header***``, segments per Express VI call, LVM 2.0's
    ``Decimal_Separator``); NI LabVIEW help "LabVIEW-Messwertdateien" (six decimals); an
    open-source LVM parser's list of required file-header keys.

    Map: no ``[time]`` (the X column); torque [N.m], encoder counts, pressure [bar].
    """
    rec = rec if rec is not None else bench_recording()
    path = Path(folder) / name
    names = {
        "torque": "Torque",
        "wheel_encoder_counts": "Wheel encoder",
        "roller_encoder_counts": "Roller encoder",
        "air_spring_pressure": "Air spring",
    }
    present = _present(rec, names)
    t = rec.time - rec.time[0]
    dt = float(np.median(np.diff(t)))
    local = _local(start, 0.0)
    date, clock = local.strftime("%Y/%m/%d"), local.strftime("%H:%M:%S.%f")
    m = len(present)
    head = [
        "LabVIEW Measurement\t",
        "Writer_Version\t2",
        "Reader_Version\t2",
        "Separator\tTab",
        "Decimal_Separator\t.",
        "Multi_Headings\tNo",
        "X_Columns\tOne",
        "Time_Pref\tRelative",
        "Operator\trig",
        f"Date\t{date}",
        f"Time\t{clock}",
        "***End_of_Header***\t",
        "\t",
    ]
    lines = list(head)
    half = t.size // 2
    for a, b in ((0, half), (half, t.size)):
        lines += [
            f"Channels\t{m}" + "\t" * m,
            "Samples\t" + "\t".join([str(b - a)] * m),
            "Date\t" + "\t".join([date] * m),
            "Time\t" + "\t".join([clock] * m),
            "X_Dimension\t" + "\t".join(["Time"] * m),
            "X0\t" + "\t".join([f"{t[a]:.16E}"] * m),
            "Delta_X\t" + "\t".join([f"{dt:.6f}"] * m),
            "***End_of_Header***" + "\t" * (m + 1),
            "X_Value\t" + "\t".join(col for _, col, _ in present) + "\tComment",
        ]
        cols = [_fmt(t[a:b], 6)] + [_fmt(_vendor(rec, c, u)[a:b], 6) for c, _, u in present]
        lines += ["\t".join(row) for row in zip(*cols, strict=True)]
    path.write_bytes(("\r\n".join(lines) + "\r\n").encode("ascii"))
    cmap = _map_text(
        "LabVIEW Measurement File (.lvm), two segments",
        {c: (col, _MAP_UNITS.get(u, u)) for c, col, (u, _) in present},
    )
    facts = {
        "tool": "LabVIEW Write To Measurement File (.lvm)",
        "sample_rate_Hz": 1.0 / dt,
        "segments": 2,
        "n_samples": t.size,
        "source": rec,
        "quirks": ["file header + segment headers", "X_Value column", "Comment column"],
    }
    return VendorFile(path, cmap, facts)


# ---------------------------------------------------------------------------------------------
# MATLAB


def _mat73_cell(f, group, key: str, values: np.ndarray, kind: str) -> None:
    """``values`` as a MATLAB v7.3 n x 1 cell array ``group/key`` (targets in ``#refs#``)."""
    import h5py

    refs = f.require_group("#refs#")
    if kind == "scalars":
        elements = [np.array([[v]]) for v in values]
    elif kind == "arrays":
        elements = [part.reshape(1, -1) for part in np.array_split(values, 3)]
    elif kind == "text":
        elements = [f"{v:.3f} s" for v in values[:5]]
    else:
        raise ValueError(f"time_cell must be 'scalars', 'arrays' or 'text', got {kind!r}")
    out = np.empty((1, len(elements)), dtype=h5py.ref_dtype)
    for k, element in enumerate(elements):
        if isinstance(element, str):
            codes = np.frombuffer(element.encode("utf-16-le"), dtype=np.uint16).reshape(-1, 1)
            ds = refs.create_dataset(f"{key}{k}", data=codes)
            ds.attrs["MATLAB_class"] = np.bytes_("char")
            ds.attrs["MATLAB_int_decode"] = np.int32(2)
        else:
            ds = refs.create_dataset(f"{key}{k}", data=element)
            ds.attrs["MATLAB_class"] = np.bytes_("double")
        out[0, k] = ds.ref
    cell = group.create_dataset(key, data=out, dtype=h5py.ref_dtype)
    cell.attrs["MATLAB_class"] = np.bytes_("cell")


def matlab_struct_mat(
    folder: str | Path,
    rec: Recording | None = None,
    *,
    version: str = "5",
    name: str | None = None,
    time_cell: str | None = None,
) -> VendorFile:
    """A MATLAB R2020-R2024 ``save`` of a struct of signals (``-v7``/v5 or ``-v7.3``/HDF5).

    Reproduces the way rig scripts store a test: one struct variable ``Messung`` whose fields
    are column vectors (``Zeit`` [s], ``Drehmoment`` [Nm], ``n_Rad``, ``n_Rolle`` [1/min],
    ``p_Luftfeder`` [bar]) and a nested struct ``Einheiten`` of unit strings; v5: compressed
    (``-v7``, scipy's ``savemat``); v7.3: HDF5 with the 512-byte MATLAB header (text, version
    0x0200, ``IM``), a group with ``MATLAB_class`` "struct", doubles with ``MATLAB_class``
    "double" stored transposed (an n x 1 column as HDF5 shape (1, n)) and chars as uint16 with
    ``MATLAB_int_decode`` 2.

    ``time_cell`` (v7.3 only): the time ``Zeit`` as a cell array, as scripts that collect
    samples in a loop leave it: ``"scalars"`` (one cell per sample, ``Zeit{k} = t``),
    ``"arrays"`` (a cell of three column vectors, one per acquisition block) or ``"text"`` (a
    cell of ``datestr`` strings: not numbers). MATLAB stores a cell as a dataset of HDF5 object
    references (``MATLAB_class`` "cell", shape (1, n) for an n x 1 cell) whose targets live in
    the group ``#refs#``, each a dataset with its own ``MATLAB_class``.

    Sources: MathWorks "MAT-File Versions" (v7.3 is HDF5-based); scipy.io.savemat; the MATLAB
    7.3 layout as written by rollerrig's own writer (``measure/writers.py``) and read by
    pymatreader (its ``_hdf5todict`` dereferences ``MATLAB_class`` "cell" datasets).

    Map: ``[time]`` "Messung.Zeit" [s]; channels "Messung.<field>".
    """
    rec = rec if rec is not None else bench_recording()
    version = str(version)
    path = Path(folder) / (name or f"matlab-struct-v{version.replace('.', '')}.mat")
    fields = {
        "torque": "Drehmoment",
        "wheel_speed": "n_Rad",
        "roller_speed": "n_Rolle",
        "air_spring_pressure": "p_Luftfeder",
    }
    present = _present(rec, fields)
    t = rec.time - rec.time[0]
    data = {"Zeit": t}
    data.update({col: _vendor(rec, c, u) for c, col, u in present})
    units = {"Zeit": "s", **{col: u for _, col, (u, _) in present}}
    if version == "5":
        from scipy.io import savemat

        struct = {k: v.reshape(-1, 1) for k, v in data.items()}
        struct["Einheiten"] = units
        savemat(str(path), {"Messung": struct}, format="5", do_compression=True)
    elif version == "7.3":
        import h5py

        with h5py.File(path, "w", userblock_size=512, libver="earliest") as f:
            g = f.create_group("Messung")
            g.attrs["MATLAB_class"] = np.bytes_("struct")
            for key, values in data.items():
                if key == "Zeit" and time_cell is not None:
                    _mat73_cell(f, g, key, np.asarray(values, dtype=float), time_cell)
                    continue
                ds = g.create_dataset(key, data=np.asarray(values, dtype=float).reshape(1, -1))
                ds.attrs["MATLAB_class"] = np.bytes_("double")
            u = g.create_group("Einheiten")
            u.attrs["MATLAB_class"] = np.bytes_("struct")
            for key, text in units.items():
                codes = np.frombuffer(text.encode("utf-16-le"), dtype=np.uint16).reshape(-1, 1)
                ds = u.create_dataset(key, data=codes)
                ds.attrs["MATLAB_class"] = np.bytes_("char")
                ds.attrs["MATLAB_int_decode"] = np.int32(2)
        text = (
            "MATLAB 7.3 MAT-file, Platform: PCWIN64, Created on: Mon Aug  5 13:46:13 2024 "
            "HDF5 schema 1.00 ."
        )
        header = text.encode("ascii").ljust(116, b" ") + b" " * 8 + b"\x00\x02" + b"IM"
        with path.open("r+b") as fh:
            fh.write(header.ljust(512, b"\x00"))
    else:
        raise ValueError(f"version must be '5' or '7.3', got {version!r}")
    cmap = _map_text(
        f"MATLAB v{version} struct of signals",
        {c: (f"Messung.{col}", _MAP_UNITS.get(u, u)) for c, col, (u, _) in present},
        time={"column": "Messung.Zeit", "unit": "s"},
    )
    facts = {
        "tool": f"MATLAB save -v{'7' if version == '5' else '7.3'}",
        "sample_rate_Hz": rec.sample_rate,
        "source": rec,
        "quirks": ["struct of column vectors", "nested struct of unit strings"],
    }
    return VendorFile(path, cmap, facts)
