"""The end-to-end demonstration on the bundled rig: simulate, record, read back, analyse, report.

Everything goes through the real file formats: the adhesion test is written as an NI TDMS file
(as the rig's NI USB-6341 at 250 Hz), the free-rolling runs as ASAM MDF4 files (as the HBM
QuantumX at 600 Hz), and both are read back with the channel map before analysis.
"""

from __future__ import annotations

import time
from pathlib import Path

from rollerrig.experiment.protocol import protocol_from_toml_string

__all__ = ["FREE_ROLLING_SPEEDS_KMH", "explain_free_rolling", "run_demo"]

FREE_ROLLING_SPEEDS_KMH = (5.0, 10.0, 20.0, 30.0)
"""Speeds of the free-rolling runs for the spectral study (the seed's 5/10/20/30 km/h)."""

_FREE_ROLLING = """
[experiment]
name = "free-rolling-{speed:02.0f}kmh"
description = "Free rolling (no wheel torque) at {speed:g} km/h, for spectra (Kayaalp 4.5.2.4)."
normal_load_kN = 4.3
friction = "dry"
roller_speed_kmh = {speed}
[[step]]
action = "hold"
duration_s = {duration}
"""


def explain_free_rolling(paths, rig):
    """The demo's free-rolling spectra: the one spectrum workflow, exactly as
    ``rollerrig spectrum <paths> --coherence displacement_torque_sensor`` runs it (settings from
    each signal, the coupled twin's damped modes, the coherence from the same segments).

    Returns
    -------
    recordings : list of Recording
        The recordings read back, with the derived quantities.
    spectra : rollerrig.signal.workflow.SpectraSet
    """
    from rollerrig.measure.quantities import derive_quantities
    from rollerrig.measure.readers import read_recording
    from rollerrig.signal.workflow import explain_recordings

    free = [derive_quantities(read_recording(p), rig) for p in paths]
    return free, explain_recordings(
        free, "torque", rig, coherence_with="displacement_torque_sensor"
    )


def _relocated(recording, path):
    """The recording with ``metadata["source"]`` naming where its file ends up."""
    from rollerrig.measure.recording import Recording

    meta = {**recording.metadata, "source": str(path)}
    return Recording(recording.time, recording.channels, recording.units, meta)


def run_demo(out, console=None, free_rolling_duration: float = 20.0, *, workdir=None) -> dict:
    """Run the demonstration and write everything to ``out``; returns the written paths.

    ``workdir``: write the files there instead (e.g. a staging folder whose files are moved
    into ``out`` once everything succeeded); sources and provenance still name ``out``.
    """
    import xarray as xr

    from rollerrig.measure.analysis import analyze_test, recording_facts
    from rollerrig.measure.readers import read_recording
    from rollerrig.measure.synthetic import synthetic_recording
    from rollerrig.measure.writers import write_recording
    from rollerrig.report._io import atomic_write, save_figure, write_json
    from rollerrig.report.analysis import write_analysis
    from rollerrig.report.spectra import coherence_figure, order_map_figure, spectrum_figure
    from rollerrig.report.twin import experiment_figure
    from rollerrig.rig.parameters import default_rig
    from rollerrig.solve.simulation import Simulation

    def say(text: str) -> None:
        if console is not None:
            console.print(text)

    final = Path(out)  # where the files end up: what sources and provenance name
    out = final if workdir is None else Path(workdir)
    out.mkdir(parents=True, exist_ok=True)
    rig = default_rig()
    written: dict[str, Path] = {}
    start = time.perf_counter()

    say("1/4 simulating the 30 km/h dry adhesion test on the digital twin (compiles once) ...")
    twin = Simulation(rig, "seed-30kmh-dry", output_rate=1000.0).run()
    written["twin_figure"] = save_figure(experiment_figure(twin), out / "twin-seed-30kmh-dry.png")

    say("2/4 writing what the DAQ records: NI TDMS at 250 Hz, truth beside it (NetCDF) ...")
    recording, truth = synthetic_recording(twin, sample_rate=250.0, seed=1)
    truth.attrs["provenance"] = twin.attrs["provenance"]
    tdms = write_recording(recording, out / "seed-30kmh-dry.tdms", overwrite=True)
    written["recording"] = tdms
    written["truth"] = atomic_write(
        out / "seed-30kmh-dry-truth.nc", lambda p: truth.to_netcdf(p, engine="h5netcdf")
    )

    say("3/4 free rolling at 5/10/20/30 km/h, recorded as ASAM MDF4 at 600 Hz ...")
    mdf_paths = []
    for speed in FREE_ROLLING_SPEEDS_KMH:
        protocol = protocol_from_toml_string(
            _FREE_ROLLING.format(speed=speed, duration=free_rolling_duration)
        )
        ds = Simulation(rig, protocol, output_rate=1200.0).run()
        rec, _ = synthetic_recording(ds, sample_rate=600.0, seed=int(speed))
        mdf_paths.append(write_recording(rec, out / f"{protocol.name}.mf4", overwrite=True))

    say("4/4 reading the files back and analysing ...")
    test = _relocated(read_recording(tdms), final / tdms.name)  # rollerrig's own channel map
    result = analyze_test(test, rig, truth=xr.load_dataset(written["truth"], engine="h5netcdf"))
    free, spectra = explain_free_rolling(mdf_paths, rig)
    explained, fixed = list(spectra.spectra), spectra.speed_independent
    for path, e in zip(mdf_paths, explained, strict=True):
        written[path.stem] = save_figure(
            spectrum_figure(e, max_frequency=60.0, title=path.name), out / f"{path.stem}.png"
        )
    # Shaft displacement (laser at the torque sensor) against torque at 30 km/h (Kayaalp 4.5.2.4).
    e30 = explained[-1]
    coh, coh_at_peaks = e30.coherence, e30.coherence_at_peaks()
    omap = spectra.order_map()
    written["order_map"] = save_figure(
        order_map_figure(omap, roller_radius=rig.geometry.roller_radius_x, max_frequency=60.0),
        out / "order-map.png",
    )
    spectra_summary = {  # sources named where the files end up (not a staging folder)
        path.name: {**e.summary(), "source": str(final / path.name)}
        for path, e in zip(mdf_paths, explained, strict=True)
    }
    spectra_summary["speed_independent_lines [Hz]"] = [float(f) for f in fixed]
    spectra_summary["coherence_torque_displacement_30kmh"] = [
        {"frequency [Hz]": r.frequency, "source": r.label, "coherence": g}
        for r, g in zip(e30.rows, coh_at_peaks, strict=True)
    ]

    def free_rolling_section(rep):
        rep.heading("Free rolling at 5, 10, 20 and 30 km/h: where every line comes from")
        rep.paragraph(
            "Torque spectra of four free-rolling recordings (ASAM MDF4, 600 Hz). Lines that move "
            "with speed are orders of the induction motor's electrical frequency, of the wheel "
            "and roller rotation, or the PMSM's; lines that stay put at every speed are "
            f"speed-independent (found: {', '.join(f'{f:.3f} Hz' for f in fixed) or 'none'})."
        )
        rep.figure(
            order_map_figure(omap, roller_radius=rig.geometry.roller_radius_x, max_frequency=60.0),
            "Order map: peak frequency vs speed.",
        )
        for path, e in zip(mdf_paths, explained, strict=True):
            rep.figure(spectrum_figure(e, max_frequency=60.0, title=path.name), path.name)
        rep.heading("Does the shaft's run-out cause the torque lines? Coherence at 30 km/h")
        rep.paragraph(
            "Magnitude-squared coherence between the laser displacement at the torque sensor and "
            "the torque, at each torque peak. Lines that come from the shaft's eccentricity "
            "cohere (the roller orders); the induction motor's lines do not: they are not "
            "mechanical run-out, as the seed concluded (§4.5.2.4). Same segments as the "
            f"spectrum: {e30.caption()}."
        )
        rep.figure(
            coherence_figure(
                coh,
                [r.frequency for r in e30.rows],
                [r.label for r in e30.rows],
                names=("torque", "displacement"),
                max_frequency=60.0,
            ),
            "Coherence between shaft displacement and torque.",
        )
        rep.table(
            ["f [Hz]", "source", "coherence γ² [-]"],
            [
                [r.frequency, r.label, "–" if g is None else g]
                for r, g in zip(e30.rows, coh_at_peaks, strict=True)
            ],
        )

    paths = write_analysis(
        result,
        out,
        tdms.stem,
        source=str(final / tdms.name),
        truth=xr.load_dataset(written["truth"], engine="h5netcdf"),
        extra_provenance={
            "rig": rig.meta.name,
            "free_rolling": [str(final / p.name) for p in mdf_paths],
        },
        extra_sections=free_rolling_section,
    )
    written.update({p.name: p for p in paths})
    # What the reader/generator said about each free-rolling recording (notes, injected lines).
    spectra_summary["recordings"] = {
        path.name: {**recording_facts(r), "source": str(final / path.name)}
        for path, r in zip(mdf_paths, free, strict=True)
    }
    written["spectra"] = write_json(out / "free-rolling-spectra.json", spectra_summary)
    say(f"done in {time.perf_counter() - start:.1f} s")
    return {"result": result, "explained": explained, "speed_independent": fixed, **written}
