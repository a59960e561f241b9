"""Issue 26, part A: every bad input and fault found by trying the command line as a new user would.

Each entry runs ``frustum`` in-process and asserts: the documented exit
status (2 for bad input, 1 for a study in which nothing ran, 75 for a held
workflow lock), no traceback, one ``frustum: error:`` line naming the option
or field, the fix where there is one, and every file of the user's
byte-identical afterwards. Nothing here computes more than one 2-s record.
"""

import math
import os
import shutil
from pathlib import Path

import pytest
from cli_files import TINY_STUDY, snapshot, unchanged

from pipeline.cli import main

OUT = "--out"
SIM = ["simulate", "--column", "0.5,0.4,4", "--record", "SYN-RICKER"]
HAZARD = Path(__file__).parents[1] / "data" / "hazard" / "hazard_curve-mean-PGA_1.csv"
# a compliant row of two columns of two drums and a capital, and a frame of two bare columns at 2 m
DRUM_ROW = SIM + ["--model", "3d-compliant", "--drums", "2", "--capital", "1.0,0.4", "--colonnade", "2",
                  "--interaxial", "2", "--epistyle", "0.5"]
FRAME = SIM + ["--model", "2d-frame", "--colonnade", "2", "--interaxial"]


# (id, argv with {placeholders} of the files fixture, exit status, fragments of the error line)
CATALOGUE = [
    # outputs that would replace an input or a user's file
    ("fragility-over-its-results", ["fragility", "{results}", OUT, "{results}"], 2,
     ["--out", "is the results file this command reads", "give another file name"]),
    ("fragility-over-text", ["fragility", "{results}", OUT, "{notes}"], 2,
     ["exists and is not a netCDF result written by frustum", "give another file name or remove it"]),
    ("fragility-over-histories", ["fragility", "{results}", OUT, "{histories}"], 2,
     ["is a histories file of 'frustum simulate'"]),
    ("study-over-its-study-file", ["study", "run", "{study}", OUT, "{study}", "--serial"], 2,
     ["is the study file this command reads"]),
    ("study-over-text", ["study", "run", "{study}", OUT, "{notes}", "--serial"], 2,
     ["exists and is not a netCDF result written by frustum"]),
    ("study-over-fragility", ["study", "run", "{study}", OUT, "{fragility}", "--serial"], 2,
     ["is a fragility file of 'frustum fragility'"]),
    ("simulate-over-text", SIM + [OUT, "{notes}"], 2, ["exists and is not a netCDF result written by frustum"]),
    ("simulate-over-study-file", SIM + [OUT, "{study}"], 2, ["exists and is not a netCDF result"]),
    ("simulate-over-its-record", ["simulate", "--column", "0.5,0.4,4", "--record", "{record}", "--units", "g",
                                  "--dt", "0.01", "--missing-y", "zero", OUT, "{record}"], 2,
     ["is the record file this command reads"]),
    ("simulate-over-study-results", SIM + [OUT, "{results}"], 2, ["is a results file of 'frustum study run'"]),
    ("simulate-plot-over-record", ["simulate", "--column", "0.5,0.4,4", "--record", "{record_png}", OUT,
                                   "{tmp}/h.nc", "--plot", "{record_png}"], 2,
     ["--plot", "is the record file this command reads"]),
    ("report-over-a-file", ["report", "{results}", OUT, "{notes}", "--bootstrap", "0"], 2,
     ["is a file, not a folder"]),
    ("report-over-its-results", ["report", "{report_dir}/fragility.nc", OUT, "{report_dir}", "--bootstrap", "0"], 2,
     ["is the results file this command reads"]),
    ("animate-over-its-results", ["animate", "{histories}", OUT, "{histories}"], 2,
     ["give a file name ending in .gif or .mp4"]),
    ("workflow-two-steps-one-output", ["workflow", "run", "{wf_duplicate}"], 2,
     ["field steps[1].output", "is also written by steps[0].output", "give every step its own output"]),
    ("workflow-output-is-a-study", ["workflow", "run", "{wf_output_is_study}"], 2,
     ["field steps[0].output", "is the study file of steps[0] this command reads"]),
    ("workflow-log-is-a-study", ["workflow", "run", "{wf_log_is_study}"], 2, ["field log", "this command reads"]),
    # figures, animations and reports over a user's file of the same suffix (a photo, notes)
    ("simulate-plot-over-a-photo", SIM + [OUT, "{tmp}/h.nc", "--plot", "{photo_png}"], 2,
     ["--plot", "photo.png' exists and was not written by frustum", "give another file name or remove it"]),
    ("simulate-plot-of-two-models-over-a-photo", SIM + [OUT, "{tmp}/h.nc", "--model", "3d,2d", "--plot",
                                                  "{tmp}/site.png"], 2,
     ["--plot", "site_2d.png' exists and was not written by frustum"]),
    ("simulate-animate-over-a-photo", SIM + [OUT, "{tmp}/h.nc", "--animate", "{photo_gif}"], 2,
     ["--animate", "photo.gif' exists and was not written by frustum", "give another file name or remove it"]),
    ("animate-over-a-photo", ["animate", "{histories}", OUT, "{photo_gif}"], 2,
     ["--out", "photo.gif' exists and was not written by frustum", "give another file name or remove it"]),
    ("records-plot-over-a-photo", ["records", "plot", "SYN-RICKER", OUT, "{photo_png}"], 2,
     ["--out", "photo.png' exists and was not written by frustum"]),
    ("study-plot-over-a-photo", ["study", "run", "{study}", OUT, "{tmp}/s.nc", "--plot", "{photo_png}", "--serial"],
     2, ["--plot", "photo.png' exists and was not written by frustum"]),
    ("risk-plot-over-a-photo", ["risk", "{fragility}", "--hazard", "{hazard}", OUT, "{tmp}/r.nc", "--plot",
                                "{photo_png}"], 2, ["--plot", "photo.png' exists and was not written by frustum"]),
    ("workflow-plot-over-a-photo", ["workflow", "run", "{wf_plot_is_photo}"], 2,
     ["field steps[0].plot", "photo.png' exists and was not written by frustum"]),
    ("report-over-a-users-report-md", ["report", "{results}", OUT, "{notes_dir}", "--bootstrap", "0"], 2,
     ["--out", "report.md exists and was not written by frustum", "give another folder or remove that file"]),
    ("report-over-a-users-figure", ["report", "{results}", OUT, "{photos_dir}", "--bootstrap", "0"], 2,
     ["--out", "figures/site.png exists and was not written by frustum", "give another folder"]),
    ("report-over-a-users-csv", ["report", "{results}", OUT, "{table_dir}", "--bootstrap", "0"], 2,
     ["summary.csv exists and is not a summary.csv written by 'frustum report'", "give another folder"]),
    # bad values of options
    ("simulate-output-step-0", SIM + [OUT, "{tmp}/h.nc", "--output-step", "0"], 2,
     ["--output-step 0.0", "positive number of seconds"]),
    ("simulate-output-step-nan", SIM + [OUT, "{tmp}/h.nc", "--output-step", "nan"], 2, ["--output-step nan"]),
    ("simulate-output-step-tiny", SIM + [OUT, "{tmp}/h.nc", "--output-step", "5e-324"], 2,
     ["--output-step", "larger --output-step"]),
    ("simulate-output-step-longer-than-the-run", SIM + [OUT, "{histories}", "--output-step", "100"], 2,
     ["--output-step 100: longer than the run (record 3 s + --tail 5 s = 8 s)", "give at most 8 s",
      "or a longer --tail"]),
    ("simulate-free-output-step-longer-than-the-run", ["simulate", "--column", "0.5,0.4,4", "--theta0", "5",
                                                       "--duration", "2", "--output-step", "3", OUT, "{histories}"],
     2, ["--output-step 3: longer than the run (--duration = 2 s)", "give at most 2 s"]),
    ("simulate-tail-nan", SIM + [OUT, "{tmp}/h.nc", "--tail", "nan"], 2, ["--tail nan", "[0, 3600]"]),
    ("animate-fps-1e6", ["animate", "{histories}", OUT, "{tmp}/a.gif", "--fps", "1000000"], 2,
     ["--fps 1e+06", "between 0.1 and 100"]),
    ("animate-fps-0", ["animate", "{histories}", OUT, "{tmp}/a.gif", "--fps", "0"], 2, ["--fps 0"]),
    ("animate-speed-1e-9", ["animate", "{histories}", OUT, "{tmp}/a.gif", "--speed", "1e-9"], 2,
     ["--speed 1e-09", "frames", "lower --fps or raise --speed"]),
    ("animate-speed-nan", ["animate", "{histories}", OUT, "{tmp}/a.gif", "--speed", "nan"], 2, ["--speed nan"]),
    ("animate-dpi-0", ["animate", "{histories}", OUT, "{tmp}/a.gif", "--dpi", "0"], 2,
     ["--dpi 0", "between 10 and 600"]),
    ("fragility-bootstrap-negative", ["fragility", "{results}", OUT, "{tmp}/f.nc", "--bootstrap", "-1"], 2,
     ["--bootstrap -1"]),
    ("fragility-confidence-nan", ["fragility", "{results}", OUT, "{tmp}/f.nc", "--confidence", "nan"], 2,
     ["--confidence nan"]),
    ("report-bootstrap-negative", ["report", "{results}", OUT, "{tmp}/rep", "--bootstrap", "-1"], 2,
     ["--bootstrap -1"]),
    # outputs that cannot be written: the one message of simulate and study
    ("simulate-out-unwritable", SIM + [OUT, "/proc/frustum-test/h.nc"], 2, ["/proc cannot be written"]),
    ("study-out-unwritable", ["study", "run", "{study}", OUT, "/proc/frustum-test/s.nc"], 2,
     ["/proc cannot be written"]),
    ("report-out-unwritable", ["report", "{results}", OUT, "/proc/frustum-test/rep", "--bootstrap", "0"], 2,
     ["--out '/proc/frustum-test/rep': /proc cannot be written", "choose a folder you may write in"]),
    ("animate-out-unwritable", ["animate", "{histories}", OUT, "/proc/frustum-test/a.gif"], 2,
     ["--out '/proc/frustum-test/a.gif': /proc cannot be written"]),
    ("simulate-animate-unwritable", SIM + [OUT, "{tmp}/h.nc", "--animate", "/proc/frustum-test/a.gif"], 2,
     ["--animate '/proc/frustum-test/a.gif': /proc cannot be written"]),
    ("workflow-log-unwritable", ["workflow", "run", "{wf_log_unwritable}"], 2,
     ["field log '/proc/frustum-test/wf.log': /proc cannot be written"]),
    # files that cannot be read
    ("animate-truncated-netcdf", ["animate", "{truncated}", OUT, "{tmp}/a.gif"], 2,
     ["cannot be read as netCDF", "run it again"]),
    ("animate-frame-that-does-not-say-its-row", ["animate", "{old_frame}", OUT, "{tmp}/a.gif"], 2,
     ["the 2d-frame run does not say which colonnade ran (no attribute n_columns)", "run 'frustum simulate' again"]),
    # failures that looked like success
    ("report-every-cell-failed", ["report", "{failed}", OUT, "{tmp}/rep", "--bootstrap", "0"], 2,
     ["simulations failed (status 1), so there is nothing to report"]),
    ("report-a-body-label-of-another-scheme", ["report", "{foreign_labels}", OUT, "{tmp}/rep", "--bootstrap", "0"], 2,
     ["foreign.nc: variable 'overturn_body': body label 'column 2 pillar' is not one this project writes",
      "run the study again with 'frustum study run'"]),
    ("records-units-on-catalog-id", ["records", "show", "SYN-RICKER", "--units", "g"], 2,
     ["--units: SYN-RICKER is a catalog record", "drop --units"]),
    ("study-unreachable-scheduler", ["study", "run", "{study}", OUT, "{tmp}/s.nc", "--scheduler",
                                     "tcp://127.0.0.1:9", "--quiet"], 2, ["--scheduler", "cannot connect"]),
    ("study-every-cell-failed", ["study", "run", "{study}", OUT, "{tmp}/s.nc", "--serial", "--quiet"], 1,
     ["all 1 cells of the study failed", "the first: record ricker:", "found no rebound peak"]),
    # a study is refused before computing whatever the command line would refuse (issue 38, item 1)
    ("study-check-step-above-the-stability-limit", ["study", "check", "{study_step}"], 2,
     ["field options.step: column 'paper', model 3d-compliant: step = 0.01 s is above twice the stability limit",
      "give a step of at most"]),
    ("study-run-step-above-the-stability-limit", ["study", "run", "{study_step}", "--serial", "--quiet"], 2,
     ["field options.step: column 'paper', model 3d-compliant: step = 0.01 s is above twice the stability limit"]),
    ("study-check-variant-step-above-the-stability-limit", ["study", "check", "{study_variant_step}"], 2,
     ["field models.a.options.step: column 'paper', model a: step = 0.005 s is above twice the stability limit"]),
    ("study-explicit-springs-at-their-limit", ["study", "check", "{study_explicit_limit}"], 2,
     ["field models.a: column 'paper', model a: step_safety = 1", "at or above the stability limit",
      "springs = explicit", "give a step below", "or springs = implicit"]),
    ("study-springs-unknown", ["study", "check", "{study_springs_unknown}"], 2,
     ["field models.a.numerics.springs: 'backward' is unknown; choose one of 'implicit', 'explicit'"]),
    ("study-option-no-model-reads", ["study", "check", "{study_rigid_step}"], 2,
     ["field options.step: no model of the study reads step (3d does not read it)",
      "it is an option of 3d-compliant: remove it, or run a model that reads it"]),
    ("study-drums-of-rigid-models", ["study", "check", "{study_rigid_drums}"], 2,
     ["field columns[0].drums: no model of the study runs drums", "drums are run by 3d-compliant"]),
    ("study-body-of-a-rigid-variant", ["study", "check", "{study_rigid_body}"], 2,
     ["field models.a.body", "body is read by models of drums (3d-compliant): remove it"]),
    ("study-step-and-step-safety", ["study", "check", "{study_step_safety}"], 2,
     ["field models.a.numerics.step_safety: a does not read step_safety with step = 0.001",
      "read only with step not given", "give one of them"]),
    ("study-variant-named-as-another-model", ["study", "check", "{study_named_2d}"], 2,
     ["field models.2d: a variant of 3d may not be named '2d', the name of the registry model 2d",
      "give it a name of its own"]),
    ("study-workers-with-scheduler", ["study", "run", "{study}", "--scheduler", "tcp://127.0.0.1:9", "--workers", "2"],
     2, ["--workers 2 is the size of the local cluster", "--scheduler tcp://127.0.0.1:9 runs on the workers of that "
         "cluster", "drop --workers, or drop --scheduler"]),
    ("study-workers-with-serial", ["study", "run", "{study}", "--serial", "--workers", "2"], 2,
     ["--workers 2 is the size of the local cluster", "--serial runs in this process"]),
    ("report-reference-not-in-the-results", ["report", "{results}", OUT, "{tmp}/rep", "--bootstrap", "0",
                                             "--reference", "stack"], 2,
     ["--reference 'stack' is not a model of", "its models are 3d: give one of them"]),
    # issue 38, item 2: hazard files refused naming what is wrong; a negative number after any flag of any
    # subcommand reaches the option's own check (argparse said "expected one argument")
    ("risk-hazard-level-no-motion-reaches", ["risk", "{fragility}", "--hazard", "{hazard_1e300}", OUT, "{tmp}/r.nc"],
     2, ["level-1e300.csv: column 'poe-1e300': a level of 1e+300 g is beyond any ground motion",
         "levels up to 30 g are accepted", "give each level in g"]),
    ("risk-hazard-semicolons", ["risk", "{fragility}", "--hazard", "{hazard_semicolons}", OUT, "{tmp}/r.nc"], 2,
     ["semicolons.csv: the fields are separated by ';'", "save the file as comma-separated"]),
    ("risk-hazard-without-metadata-row", ["risk", "{fragility}", "--hazard", "{hazard_no_metadata}", OUT,
                                          "{tmp}/r.nc"], 2,
     ["no-metadata.csv: the first line is the header", "starts with a '#' row of metadata", "investigation_time"]),
    ("risk-hazard-header-trailing-comma", ["risk", "{fragility}", "--hazard", "{hazard_trailing_comma}", OUT,
                                           "{tmp}/r.nc"], 2,
     ["trailing-comma.csv: the header ends in an empty column (a trailing comma after 'poe-2.0000000')"]),
    ("report-hazard-semicolons", ["report", "{results}", OUT, "{tmp}/rep", "--hazard", "{hazard_semicolons}"], 2,
     ["semicolons.csv: the fields are separated by ';'"]),
    ("simulate-step-negative-exponent", SIM + ["--model", "3d-compliant", "--step", "-1e-5", OUT, "{tmp}/h.nc"], 2,
     ["step", "-1e-05"]),
    ("simulate-tail-negative-exponent", SIM + [OUT, "{tmp}/h.nc", "--tail", "-1e-3"], 2,
     ["--tail -0.001", "[0, 3600]"]),
    ("simulate-scale-minus-inf", SIM + [OUT, "{tmp}/h.nc", "--scale", "-inf"], 2, ["scale = -inf", "positive"]),
    ("risk-years-negative-exponent", ["risk", "{fragility}", "--hazard", "{hazard}", OUT, "{tmp}/r.nc", "--years",
                                      "-5e1"], 2, ["--years -50: give a positive number of years"]),
    ("report-years-negative-exponent", ["report", "{results}", OUT, "{tmp}/rep", "--hazard", "{hazard}", "--years",
                                        "-1E2"], 2, ["--years -100: give a positive number of years"]),
    ("fragility-confidence-negative-exponent", ["fragility", "{results}", OUT, "{tmp}/f.nc", "--confidence",
                                                "-.5e-1"], 2, ["--confidence -0.05"]),
    ("animate-fps-negative-exponent", ["animate", "{histories}", OUT, "{tmp}/a.gif", "--fps", "-1e1"], 2,
     ["--fps -10", "between 0.1 and 100"]),
    ("records-dt-negative-exponent", ["records", "show", "SYN-RICKER", "--dt", "-1e-2"], 2, ["--dt -0.01"]),
    # issue 48, item 1: a hazard curve from code values, refused as a file's, by value and with the fix
    ("risk-hazard-and-hazard-pga", ["risk", "{fragility}", "--hazard", "{hazard}", "--hazard-pga", "475:0.16", OUT,
                                    "{tmp}/r.nc"], 2,
     ["and --hazard-pga 475:0.16 both give the site's hazard; give one of them"]),
    ("risk-no-hazard", ["risk", "{fragility}", OUT, "{tmp}/r.nc"], 2,
     ["give the site's hazard: --hazard CURVE.csv", "or --hazard-pga T:PGA (code values, e.g. 475:0.16)"]),
    ("risk-hazard-slope-with-a-file", ["risk", "{fragility}", "--hazard", "{hazard}", "--hazard-slope", "3", OUT,
                                       "{tmp}/r.nc"], 2,
     ["--hazard-slope 3 shapes a hazard curve from code values (--hazard-pga)", "drop --hazard-slope"]),
    ("risk-hazard-pga-malformed", ["risk", "{fragility}", "--hazard-pga", "475-0.16", OUT, "{tmp}/r.nc"], 2,
     ["--hazard-pga: '475-0.16' is not a return period and a PGA; give T:a pairs, e.g. 475:0.16"]),
    ("risk-hazard-pga-not-growing", ["risk", "{fragility}", "--hazard-pga", "475:0.24,2475:0.16", OUT,
                                     "{tmp}/r.nc"], 2,
     ["--hazard-pga: the PGA at 2475 years (0.16 g) is not above that at 475 years (0.24 g)", "check the values"]),
    ("risk-hazard-pga-twice", ["risk", "{fragility}", "--hazard-pga", "475:0.16,475:0.24", OUT, "{tmp}/r.nc"], 2,
     ["--hazard-pga: the return period 475 years is given twice (475:0.16, 475:0.24); give each once"]),
    ("risk-hazard-pga-negative", ["risk", "{fragility}", "--hazard-pga", "-475:0.16", OUT, "{tmp}/r.nc"], 2,
     ["--hazard-pga: -475:0.16: the return period -475 is not a positive number of years"]),
    ("risk-hazard-slope-out-of-range", ["risk", "{fragility}", "--hazard-pga", "475:0.16", "--hazard-slope", "0.2",
                                        OUT, "{tmp}/r.nc"], 2,
     ["--hazard-slope is 0.2; slopes of a hazard curve's power law lie between 0.5 and 10", "give one inside, e.g. 3"]),
    ("risk-years-twice", ["risk", "{fragility}", "--hazard-pga", "475:0.16", "--years", "50,50", OUT, "{tmp}/r.nc"],
     2, ["--years 50,50: a period is given twice; give each once, e.g. 50,2100"]),
    # issue 47, item 4: a check refuses what a run would fail cell by cell or silently ignore, in the words of
    # simulate (the one place of each refusal called from both)
    ("study-check-compliant-colonnade-without-capitals", ["study", "check", "{study_bare_row}"], 2,
     ["field columns[0]: column 'paper', model 3d-compliant: the compliant model runs a colonnade whose columns have "
      "capitals", "give the column a capital, or run the rigid frame (2d-frame)"]),
    ("simulate-compliant-colonnade-without-capitals", SIM + ["--model", "3d-compliant", "--colonnade", "2",
                                                             "--interaxial", "2", "--epistyle", "0.5", OUT,
                                                             "{tmp}/h.nc"], 2,
     ["frustum: error: the compliant model runs a colonnade whose columns have capitals"]),
    ("study-check-colonnade-of-rigid-models", ["study", "check", "{study_rigid_row}"], 2,
     ["field columns[0].colonnade: no model of the study runs colonnades (3d runs the column alone), so colonnade "
      "would be ignored; colonnades are run by 3d-compliant, 2d-frame: remove colonnade, or run a model of "
      "colonnades"]),
    ("simulate-colonnade-of-rigid-models", SIM + ["--model", "3d", "--colonnade", "2", "--interaxial", "2",
                                                  "--epistyle", "0.5", OUT, "{tmp}/h.nc"], 2,
     ["frustum: error: no model of the run runs colonnades (3d runs the column alone), so --colonnade would be "
      "ignored; colonnades are run by 3d-compliant, 2d-frame: drop --colonnade, or run a model of colonnades"]),
    ("simulate-drums-of-the-frame", FRAME + ["2", "--epistyle", "0.5", "--drums", "3", OUT, "{tmp}/h.nc"], 2,
     ["frustum: error: no model of the run runs drums (2d-frame runs each column as one rigid body), so --drums would "
      "be ignored; drums are run by 3d-compliant: drop --drums, or run a model of drums"]),
    ("study-check-drums-of-the-frame", ["study", "check", "{study_frame_drums}"], 2,
     ["field columns[0].drums: no model of the study runs drums (2d-frame runs each column as one rigid body), so "
      "drums would be ignored; drums are run by 3d-compliant: remove drums, or run a model of drums"]),
    ("simulate-joint-friction-list-of-a-colonnade", DRUM_ROW + ["--joint-friction", "0.6,0.5", OUT, "{tmp}/h.nc"], 2,
     ["frustum: error: joint_friction: a list gives one value per bed joint of a single column; a colonnade of 2 "
      "columns takes one number for all its joints: give one joint_friction, or run its column alone"]),
    ("simulate-anathyrosis-list-of-a-colonnade", DRUM_ROW + ["--anathyrosis", "0.2,0.3", OUT, "{tmp}/h.nc"], 2,
     ["frustum: error: anathyrosis: a list gives one value per bed joint of a single column; a colonnade of 2 "
      "columns takes one number for all its joints: give one anathyrosis, or run its column alone"]),
    ("study-check-frame-whose-columns-lie-down-first", ["study", "check", "{study_squat_frame}"], 2,
     ["field columns[0]: column 'squat', model 2d-frame: squat: its columns would lie on the ground (at 26.6 deg) "
      "before the frame tips over (at 64.8 deg)", "give a narrower capital or a more slender column"]),
    # plausibility limits of a colonnade, each with its reason
    ("simulate-interaxial-100-m", FRAME + ["100", "--epistyle", "1", OUT, "{tmp}/h.nc"], 2,
     ["colonnade interaxial = 100 m is more than 10 m: no stone epistyle is known to span so far",
      "Artemision's west front at Ephesus", "give an interaxial spacing of at most 10 m"]),
    ("simulate-epistyle-50-m-high", FRAME + ["2", "--epistyle", "50", OUT, "{tmp}/h.nc"], 2,
     ["colonnade epistyle_height = 50 m is more than 0.5 of the columns' height 4 m", "at most 2 m high"]),
    ("simulate-epistyle-1-mm-high", FRAME + ["2", "--epistyle", "0.001", OUT, "{tmp}/h.nc"], 2,
     ["colonnade epistyle_height = 0.001 m is less than 1/10 of its span (interaxial 2 m)",
      "give an epistyle at least 0.2 m high"]),
    ("study-check-epistyle-1-cm-wide", ["study", "check", "{study_thin_epistyle}"], 2,
     ["field columns[0].colonnade: colonnade epistyle_width = 0.01 m is outside 0.5 to 2 times the abacus side 0.8 m: "
      "the blocks would stand on a strip of their capitals; give a width from 0.4 to 1.6 m"]),
    # issue 48, item 2: imperfect drums, refused by simulate and a study in the same words
    ("simulate-imperfections-of-a-rigid-model", SIM + ["--imperfections", "0.002", "--seed", "1", OUT,
                                                       "{tmp}/h.nc"], 2,
     ["--imperfections draws imperfect drums (beds offset and tilted within a tolerance, joint friction from a "
      "range), which only 3d-compliant runs; model 3d runs perfect structures, so it would be ignored: drop "
      "--imperfections, or run 3d-compliant"]),
    ("study-imperfections-of-rigid-models", ["study", "check", "{study_imperfect_rigid}"], 2,
     ["field imperfections: [imperfections] draws imperfect drums (beds offset and tilted within a tolerance, "
      "joint friction from a range), which only 3d-compliant runs; model 3d runs perfect structures, so it would "
      "be ignored: drop [imperfections], or run 3d-compliant"]),
    ("simulate-imperfections-without-a-seed", SIM + ["--model", "3d-compliant", "--imperfections", "0.002", OUT,
                                                     "{tmp}/h.nc"], 2,
     ["imperfections = 0.002 m are drawn from a seed: give seed too"]),
    ("simulate-seed-negative", SIM + ["--model", "3d-compliant", "--imperfections", "0.002", "--seed", "-1", OUT,
                                      "{tmp}/h.nc"], 2,
     ["seed = -1: the seed of the imperfections' draw must be a whole number in [0, 4294967295]"]),
    ("simulate-friction-range-reversed", SIM + ["--model", "3d-compliant", "--imperfections", "0.002", "--seed", "1",
                                                "--friction-range", "0.7,0.5", OUT, "{tmp}/h.nc"], 2,
     ["friction_range = (0.7, 0.5): the range of friction coefficients each joint of a column draws from must be "
      "two numbers LO,HI with LO <= HI"]),
    ("simulate-imperfections-beyond-five-percent", SIM + ["--model", "3d-compliant", "--drums", "2", "--imperfections",
                                                          "0.1", "--seed", "1", OUT, "{tmp}/h.nc"], 2,
     ["imperfections = 0.1 m is more than 5 % of the smallest bed diameter of the columns (0.9 m)",
      "give at most 0.045 m"]),
]

#: Study files of the catalogue: the tiny study with one line replaced ({placeholder: (old, new)}).
STUDIES = {
    "study_step": ('tail = 0.5', 'tail = 0.5\nstep = 0.01', '"3d"', '"3d-compliant"'),
    "study_variant_step": ('models = ["3d"]', '[models.a]\nmodel = "3d-compliant"\noptions = {step = 0.005}'),
    "study_rigid_step": ('tail = 0.5', 'tail = 0.5\nstep = 1e-5'),
    "study_rigid_drums": ('named = "paper"', 'named = "paper"\ndrums = 3'),
    "study_rigid_body": ('models = ["3d"]', '[models.a]\nmodel = "3d"\nbody = "outline"'),
    "study_step_safety": ('models = ["3d"]', '[models.a]\nmodel = "3d-compliant"\noptions = {step = 0.001}\n'
                          'numerics = {step_safety = 0.3}'),
    "study_named_2d": ('models = ["3d"]', '[models.2d]\nmodel = "3d"'),
    "study_explicit_limit": ('models = ["3d"]', '[models.a]\nmodel = "3d-compliant"\n'
                             'numerics = {springs = "explicit", step_safety = 1.0}'),
    "study_springs_unknown": ('models = ["3d"]', '[models.a]\nmodel = "3d-compliant"\nnumerics = {springs = "backward"}'),
    "study_bare_row": ('"3d"', '"3d-compliant"', 'named = "paper"',
                       'named = "paper"\ncolonnade = {columns = 2, interaxial = 2.0, epistyle_height = 0.5}'),
    "study_rigid_row": ('named = "paper"', 'named = "paper"\ncapital = [1.0, 0.4]\n'
                        'colonnade = {columns = 2, interaxial = 2.0, epistyle_height = 0.5}'),
    "study_frame_drums": ('"3d"', '"2d-frame"', 'named = "paper"', 'named = "paper"\ndrums = 3\n'
                          'colonnade = {columns = 2, interaxial = 2.0, epistyle_height = 0.5}'),
    "study_squat_frame": ('"3d"', '"2d-frame"', 'named = "paper"', 'name = "squat"\nR = 0.5\nr = 0.4\nh = 0.5\n'
                          'capital = [3.0, 0.2]\ncolonnade = {columns = 2, interaxial = 3.0, epistyle_height = 0.3}'),
    "study_thin_epistyle": ('"3d"', '"2d-frame"', 'named = "paper"', 'named = "paper"\ncolonnade = {columns = 2, '
                            'interaxial = 2.0, epistyle_height = 0.5, epistyle_width = 0.01}'),
    "study_imperfect_rigid": ('tail = 0.5', 'tail = 0.5\n\n[imperfections]\ntolerance = 0.002\nseeds = [1, 2]'),
}

#: Hazard files of the issue 38 entries: the committed engine export, edited as a spreadsheet or a hand would.
ISSUE_38_HAZARD = {
    "hazard_1e300": ("level-1e300.csv", lambda b: b.replace(b"poe-2.0000000", b"poe-1e300")),
    "hazard_semicolons": ("semicolons.csv", lambda b: b.replace(b",", b";")),
    "hazard_no_metadata": ("no-metadata.csv", lambda b: b.split(b"\r\n", 1)[1]),
    "hazard_trailing_comma": ("trailing-comma.csv", lambda b: b.replace(b"poe-2.0000000\r\n", b"poe-2.0000000,\r\n")),
}


@pytest.fixture
def files(tmp_path, results_nc, histories_nc, failed_results_nc, old_frame_nc, foreign_labels_nc):
    """Every file a catalogue entry names, in a fresh folder: {placeholder: path}."""
    from pipeline import fragility as F

    paths = {"tmp": tmp_path}
    for name, source in (("results", results_nc), ("histories", histories_nc), ("failed", failed_results_nc),
                         ("old_frame", old_frame_nc), ("foreign_labels", foreign_labels_nc)):
        paths[name] = tmp_path / source.name
        shutil.copy(source, paths[name])
    paths["fragility"] = tmp_path / "fragility.nc"
    F.write(F.fragility(F.open_results(results_nc)), paths["fragility"])
    paths["truncated"] = tmp_path / "cut.nc"
    paths["truncated"].write_bytes(histories_nc.read_bytes()[:5000])
    paths["notes"] = tmp_path / "notes.txt"
    paths["notes"].write_text("my notes\n", encoding="utf-8")
    paths["study"] = tmp_path / "tiny.toml"
    paths["study"].write_text(TINY_STUDY, encoding="utf-8")
    for name, pairs in STUDIES.items():
        text = TINY_STUDY
        for old, new in zip(pairs[::2], pairs[1::2]):
            assert old in text, old
            text = text.replace(old, new)
        paths[name] = tmp_path / f"{name}.toml"
        paths[name].write_text(text, encoding="utf-8")
    paths["record"] = tmp_path / "record.txt"
    paths["record"].write_text("0.0\n0.1\n-0.1\n0.0\n", encoding="utf-8")
    paths["record_png"] = tmp_path / "record.png"  # a record file a plot could be named after
    paths["record_png"].write_bytes(b"\x89PNG not really\n")
    paths["report_dir"] = tmp_path / "report"
    paths["report_dir"].mkdir()
    shutil.copy(results_nc, paths["report_dir"] / "fragility.nc")
    paths["photo_png"] = tmp_path / "photo.png"  # a user's own pictures, of the suffixes frustum writes
    paths["photo_png"].write_bytes(b"\x89PNG\r\n\x1a\n a photo of the site\n")
    paths["photo_2d"] = tmp_path / "site_2d.png"  # where --model 3d,2d --plot site.png draws the 2D model
    paths["photo_2d"].write_bytes(b"\x89PNG\r\n\x1a\n a photo of the 2D rocking block\n")
    paths["photo_gif"] = tmp_path / "photo.gif"
    paths["photo_gif"].write_bytes(b"GIF89a a photo of the site\n")
    paths["hazard"] = tmp_path / "hazard_curve-mean-PGA_1.csv"
    shutil.copy(HAZARD, paths["hazard"])
    for key, (name, edit) in ISSUE_38_HAZARD.items():
        paths[key] = tmp_path / name
        paths[key].write_bytes(edit(HAZARD.read_bytes()))
    for key, name, data in (("notes_dir", "report.md", b"# my notes\n"), ("photos_dir", "figures/site.png", b"\x89PNG"),
                            ("table_dir", "summary.csv", b"column,height\nA,4\n")):
        paths[key] = tmp_path / key
        (paths[key] / name).parent.mkdir(parents=True)
        (paths[key] / name).write_bytes(data)
    for name, log, steps in (
        ("wf_duplicate", "wf.log", ['study = "tiny.toml"\noutput = "out/a.nc"', 'study = "tiny.toml"\noutput = "out/a.nc"']),
        ("wf_output_is_study", "wf.log", ['study = "tiny.toml"\noutput = "tiny.toml"']),
        ("wf_log_is_study", "tiny.toml", ['study = "tiny.toml"\noutput = "out/a.nc"']),
        ("wf_log_unwritable", "/proc/frustum-test/wf.log", ['study = "tiny.toml"\noutput = "out/a.nc"']),
        ("wf_plot_is_photo", "wf.log", ['study = "tiny.toml"\noutput = "out/a.nc"\nplot = "photo.png"']),
    ):
        paths[name] = tmp_path / f"{name}.toml"
        paths[name].write_text(f'log = "{log}"\n' + "".join(f"[[steps]]\n{s}\n" for s in steps), encoding="utf-8")
    return paths


@pytest.mark.parametrize("argv, status, fragments", [c[1:] for c in CATALOGUE], ids=[c[0] for c in CATALOGUE])
def test_bad_input(files, capsys, monkeypatch, argv, status, fragments):
    if "--serial" in argv and "{tmp}/s.nc" in argv:  # the study in which every simulation fails
        from pipeline.study import orchestrate
        from pipeline.study import run as task_run

        def fails(*args, **kwargs):
            raise ValueError("found no rebound peak")

        monkeypatch.setattr(task_run, "simulate", fails)
        monkeypatch.setattr(orchestrate, "prepare_kernels", lambda *a, **k: 0.0)
    before = snapshot(*[p for p in files["tmp"].rglob("*") if p.is_file()])
    listing = sorted(os.listdir(files["tmp"]))

    assert main([a.format(**files) for a in argv]) == status
    err = capsys.readouterr().err
    assert "Traceback" not in err
    errors = [line for line in err.splitlines() if line.startswith("frustum: error:")]
    assert len(errors) == 1, err
    for fragment in fragments:
        assert fragment in errors[0], errors[0]
    assert unchanged(before)  # every file of the user's, byte for byte
    if status == 2:  # refused before anything was written: no new file, no checkpoint, no temporary
        assert sorted(os.listdir(files["tmp"])) == listing


def test_quiet_workflow_exits_75_in_silence_when_another_run_holds_the_lock(files, capsys):
    from pipeline.locking import try_lock

    wf = files["tmp"] / "wf.toml"
    wf.write_text('log = "logs/wf.log"\n[[steps]]\nstudy = "tiny.toml"\noutput = "out/a.nc"\n', encoding="utf-8")
    (files["tmp"] / "logs").mkdir()
    held = try_lock(files["tmp"] / "logs" / "wf.log.lock")
    try:
        assert main(["workflow", "run", "--quiet", str(wf)]) == 75
    finally:
        held.release()
    assert capsys.readouterr() == ("", "")


def test_every_parser_of_the_command_reads_a_negative_number_as_a_value():
    """Issue 38, item 2: the top parser, every subcommand and every action of a subcommand take any
    '-<digit>', '-.<digit>', '-inf' or '-nan' for a value (Python 3.14's reading, pipeline.cli.Parser),
    while an option after a flag is still an option."""
    import argparse

    from pipeline.cli import Parser, build_parser

    def walk(parser, name):
        yield name, parser
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for sub, child in action.choices.items():
                    yield from walk(child, f"{name} {sub}")

    parsers = dict(walk(build_parser(), "frustum"))
    assert {"frustum simulate", "frustum study run", "frustum records show", "frustum risk"} <= set(parsers)
    assert [name for name, p in parsers.items() if not isinstance(p, Parser)] == []
    p = Parser(prog="t")
    p.add_argument("--x", type=float)
    p.add_argument("--flag", action="store_true")
    for text, value in (("-1e-5", -1e-5), ("-.5", -0.5), ("-2.5E+3", -2500.0), ("-1_000", -1000.0), ("-7", -7.0),
                        ("-inf", -math.inf), ("-Infinity", -math.inf)):
        assert p.parse_args(["--x", text]).x == value, text
    assert math.isnan(p.parse_args(["--x", "-nan"]).x)
    with pytest.raises(SystemExit):
        p.parse_args(["--x", "--flag"])  # an option is not swallowed as a value
