"""Mutation testing with mutmut: how many small deliberate bugs do the tests catch?

mutmut (3.x) changes the code one small edit at a time (an operator, a constant, an
argument dropped) and runs the tests that cover the changed function; a *surviving*
mutant is a change no test notices. The run happens in a scratch copy of the working
tree (never in the tree itself), and prints, per source file, the score (killed over
all mutants, a mutant that no selected test reaches counted as surviving) and every
survivor as a diff, to be judged: a test to add, or an equivalent mutant (one that
cannot change any result, e.g. a constant offset that cancels in a difference).

Not part of CI: a full run takes hours on 2 cores. Choose modules and tests:

    python benchmarks/mutation.py --module sktiction/features/area_ratio.py \
        --tests tests/test_area_ratio.py tests/test_estimator_checks.py
    python benchmarks/mutation.py --module sktiction/features/hysteresis.py  # its fast tests
    python benchmarks/mutation.py --module features      # a group, with its tests
    python benchmarks/mutation.py --list                 # the groups
    python benchmarks/mutation.py --module sktiction/datasets/_generators.py \
        --sample 300 --seed 0                            # a random sample of its mutants

``--sample`` runs a seeded random sample of the mutants (for files whose full run takes
hours) and prints the score with a 95 % Wilson interval; it is an estimate, say so.
``--recheck`` runs the survivors of the last run in ``--workdir`` again against the tests
as they are now (tests added since are picked up; the source stays the one measured).

Requires ``pip install mutmut`` (3.x). Runs under ``nice`` with one BLAS/numba thread
per worker; ``--max-children`` workers (default 1: the machine is shared).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import random
import shutil
import subprocess
import sys
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Module groups the issue asks for, with the tests that exercise them.
GROUPS = {
    "cycles": (
        ["sktiction/cycles/*.py"],
        ["tests/test_cycles.py", "tests/test_area_ratio.py", "tests/test_templates.py"],
    ),
    "features": (
        ["sktiction/features/*.py"],
        [
            "tests/test_area_ratio.py",
            "tests/test_templates.py",
            "tests/test_stiction_model.py",
            "tests/test_hysteresis.py",
            "tests/test_estimator_checks.py",
        ],
    ),
    "classifiers": (
        ["sktiction/classifiers/*.py"],
        [
            "tests/test_classifiers.py",
            "tests/test_shape_library.py",
            "tests/test_learned.py",
            "tests/test_applicability.py",
            "tests/test_estimator_checks.py",
        ],
    ),
    "datasets": (
        ["sktiction/datasets/*.py"],
        [
            "tests/test_make_loops.py",
            "tests/test_make_loops_signals.py",
            "tests/test_read_loops.py",
            "tests/test_timestamps.py",
            "tests/test_readers.py",
            "tests/test_example.py",
        ],
    ),
    "scan": (
        ["sktiction/reports/scan.py"],
        ["tests/test_reports.py", "tests/test_scan.py", "tests/test_properties.py"],
    ),
}

_CHECKS = "tests/test_estimator_checks.py"
# test_cleaning.py without the four tests that scan with the pretrained model or write
# and scan files (15-55 s each), and the known answers: the tests of the loop repairs
# (_cleaning.py) and of the signal repairs they build on (cycles/_repairs.py)
_CLEANING_TESTS = [
    *(f"tests/test_cleaning.py::{test}" for test in (
        "test_a_spike_of_one_to_three_samples_is_found_and_nothing_else",
        "test_a_bad_value_in_the_first_or_last_rows_is_a_spike_too",
        "test_an_end_run_beside_another_jump_is_not_a_spike",
        "test_steps_cycles_noise_and_wide_excursions_are_not_spikes",
        "test_fast_flat_topped_cycles_pulses_and_grid_flicker_are_not_spikes",
        "test_bad_values_beside_a_hole_or_each_other_are_found",
        "test_remove_spikes_draws_a_line_and_counts_what_it_replaced",
        "test_a_regular_hold_is_found_with_its_phase_and_irregular_repeats_are_not",
        "test_hidden_spike_and_hold_leave_the_scan_where_the_clean_loop_is",
        "test_a_stretch_of_placeholders_is_found_at_either_end_and_nothing_else",
        "test_codes_at_both_ends_are_judged_without_each_other",
        "test_an_outage_of_up_to_nearly_half_the_record_is_read_as_placeholders",
        "test_moves_saturation_setpoints_and_quantised_records_are_not_placeholders",
        "test_a_setpoint_with_a_hole_is_a_gap_not_a_missing_setpoint",
        "test_op_out_of_step_with_pv_is_moved_back_in_line",
        "test_op_in_step_unrelated_or_short_is_left_as_recorded",
        "test_a_controller_slower_than_the_record_is_read_at_its_own_rate",
        "test_a_pv_logged_slower_than_op_is_read_at_its_own_rate",
        "test_clean_loops_undoes_every_artefact_hidden_at_once_and_a_second_pass_finds_none",
        "test_clean_loops_refuses_what_is_not_loops_and_leaves_its_input_alone",
        "test_a_swap_is_read_from_the_controller_not_from_values_that_happen_to_agree",
        "test_a_start_up_transient_hidden_in_loops_is_found_and_dropped_and_nothing_else",
        "test_start_up_rows_at_the_edges",
        "test_the_spike_limit_is_at_least_six_tenths_of_the_five_to_95_percent_spread",
        "test_a_spike_just_before_the_last_sample_is_found",
        "test_a_slip_with_a_one_sample_overshoot_is_not_a_spike",
        "test_at_most_three_spike_samples_on_a_record_shorter_than_300",
        "test_single_codes_codes_near_zero_and_the_implausible_bound",
        "test_few_changes_are_no_grid_and_the_kept_stretch_is_in_the_input_rows",
        "test_controller_fit_is_nan_on_too_few_rows_or_an_op_that_never_moves",
        "test_a_start_up_excursion_must_reach_more_than_a_whole_range_beyond",
        "test_the_start_up_range_is_the_rest_s_half_to_99_5_percent",
        "test_the_report_holds_whole_counts_and_nan_where_nothing_was_looked_at",
        "test_one_channel_on_a_grid_needs_at_least_eight_values",
        "test_repaired_fills_absent_channels_with_nan",
        "test_as_judged_reads_loops_as_clean_loops_and_training_repairs_gaps_only",
    )),
    "tests/test_cleaning_known_answers.py",
]

#: Per file, the tests that exercise it and run in seconds (measured in docs/mutation.md);
#: ``--module <file>`` without ``--tests`` uses them.
TARGETED = {
    "sktiction/cycles/_analysis.py": ["tests/test_cycles.py"],
    "sktiction/cycles/_signal.py": ["tests/test_cycles.py", "tests/test_cycles_signal.py"],
    "sktiction/features/descriptors.py": [
        "tests/test_features_descriptors.py",
        f"{_CHECKS}::test_loop_descriptors_read_a_known_delay_and_saturation",
        f"{_CHECKS}::test_transformer_on_loops[LoopDescriptors()]",
        f"{_CHECKS}::test_bad_loops_give_a_row_and_leave_the_others_alone[LoopDescriptors()]",
    ],
    "sktiction/features/dtw.py": ["tests/test_templates.py"],
    "sktiction/features/templates.py": ["tests/test_templates.py"],
    "sktiction/features/_loops.py": ["tests/test_features_loops.py", "tests/test_templates.py"],
    "sktiction/cycles/_oscillation.py": ["tests/test_oscillation.py", "tests/test_cycles.py"],
    "sktiction/cycles/_level_shifts.py": [
        "tests/test_level_shifts.py",
        "tests/test_level_shifts_known_answers.py",
    ],
    "sktiction/features/oscillation.py": ["tests/test_oscillation.py"],
    "sktiction/features/area_ratio.py": [
        "tests/test_area_ratio.py",
        f"{_CHECKS}::test_area_ratio_of_known_half_cycles",
        f"{_CHECKS}::test_area_ratio_of_each_half_cycle",
        f"{_CHECKS}::test_area_ratio_filter_and_min_cycles_are_used",
        f"{_CHECKS}::test_loops_that_do_not_oscillate_are_said_so",
        f"{_CHECKS}::test_transformer_on_loops[AreaRatio()]",
        f"{_CHECKS}::test_bad_loops_give_a_row_and_leave_the_others_alone[AreaRatio()]",
    ],
    "sktiction/classifiers/shape_library.py": [
        "tests/test_shape_library.py",
        f"{_CHECKS}::test_classifier_on_loops[ShapeLibraryClassifier()]",
        f"{_CHECKS}::test_a_constant_op_gives_no_verdict[ShapeLibraryClassifier()]",
    ],
    "sktiction/features/template_distances.py": [
        "tests/test_templates.py",
        *(f"{_CHECKS}::{test}[{est}]"
          for test in ("test_transformer_on_loops",
                       "test_bad_loops_give_a_row_and_leave_the_others_alone")
          for est in ("TemplateDistances()", "TemplateDistances(signals=('pv',))")),
        f"{_CHECKS}::test_transformers_that_read_op_say_nothing_on_a_constant_op"
        "[TemplateDistances()]",
    ],
    "sktiction/features/stiction_model.py": [
        "tests/test_stiction_model.py",
        f"{_CHECKS}::test_transformer_on_loops[StictionModelFit()]",
        f"{_CHECKS}::test_bad_loops_give_a_row_and_leave_the_others_alone[StictionModelFit()]",
        f"{_CHECKS}::test_transformers_that_read_op_say_nothing_on_a_constant_op"
        "[StictionModelFit()]",
        f"{_CHECKS}::test_stiction_model_fit_finds_a_known_dead_band",
    ],
    "sktiction/features/hysteresis.py": [
        "tests/test_hysteresis.py",
        "tests/test_learned.py::test_hysteresis_fill_known_shapes",
        "tests/test_learned.py::test_stuck_share_sees_a_valve_that_moves_in_slips",
        "tests/test_learned.py::test_feature_transformers_are_scale_and_offset_invariant",
        f"{_CHECKS}::test_transformer_on_loops[PVOPHysteresis()]",
        f"{_CHECKS}::test_bad_loops_give_a_row_and_leave_the_others_alone[PVOPHysteresis()]",
    ],
    "sktiction/classifiers/applicability.py": [
        f"tests/test_applicability.py::{test}"
        for test in ("test_each_reason", "test_two_dimensional_input_is_pv_only",
                     "test_scale_and_offset_never_change_the_outcome",
                     "test_coherence_chance_level_holds_for_independent_noise",
                     "test_closed_loop_is_coherent_far_above_chance",
                     "test_chance_level_is_carters_bonferroni_level",
                     "test_coherence_is_scipys_at_the_better_resolution",
                     "test_segments_lose_their_straight_line",
                     "test_quantisation_snr_of_known_grids", "test_robust_spread",
                     "test_bad_input_is_refused_with_the_reason",
                     "test_lengths_sample_time_and_statistics_reached",
                     "test_held_rows_are_counted", "test_thresholds_at_their_bounds",
                     "test_control_error_is_a_second_pair_only_when_sp_moves",
                     "test_coherence_of_unrelated_signals_is_below_chance",
                     "test_edge_cases_of_the_checks", "test_quantisation_snr_bounds",
                     "test_result_columns_and_types")
    ],
    "sktiction/datasets/_timestamps.py": ["tests/test_timestamps.py", "tests/test_read_loops.py"],
    "sktiction/datasets/_readers.py": ["tests/test_readers.py", "tests/test_read_loops.py"],
    # one tiny fitted model (30 loops, 20 boosting rounds) and unit tests of its parts
    "sktiction/classifiers/learned.py": [
        "tests/test_classifiers_learned.py",
        "tests/test_learned.py::test_closed_loops_are_coupled_and_unrelated_signals_are_not",
        "tests/test_learned.py::test_bad_parameters_and_labels_raise",
        "tests/test_learned.py::test_cache_loads_rebuilds_corrupt_and_stale_entries",
    ],
    "sktiction/classifiers/_coupling.py": [
        "tests/test_classifiers_learned.py",
        "tests/test_learned.py::test_closed_loops_are_coupled_and_unrelated_signals_are_not",
    ],
    "sktiction/classifiers/_pretrained.py": [
        "tests/test_classifiers_learned.py",
        "tests/test_learned.py::test_cache_loads_rebuilds_corrupt_and_stale_entries",
        "tests/test_learned.py::test_pretrained_classifier_is_built_once_and_loaded_in_a_new_process",
    ],
    "sktiction/datasets/_generators.py": [
        "tests/test_make_loops.py", "tests/test_make_loops_signals.py",
        "tests/test_setpoint_nuisance.py", "tests/test_example.py",
        "tests/test_realism.py::test_calibrated_world_settings_reach_the_loops",
        "tests/test_generators_meta.py",
    ],
    # the worlds make_loops draws and simulates: the same tests reach them
    **{f"sktiction/datasets/{m}.py": [
        "tests/test_make_loops.py", "tests/test_make_loops_signals.py",
        "tests/test_setpoint_nuisance.py", "tests/test_example.py",
        "tests/test_realism.py::test_calibrated_world_settings_reach_the_loops",
        "tests/test_generators_meta.py",
    ] for m in ("_tuning", "_draws", "_classic_world", "_default_world")},
    "sktiction/datasets/_examples.py": [
        "tests/test_example.py", "tests/test_mutation_examples.py",
    ],
    "sktiction/datasets/_plant_examples.py": ["tests/test_mutation_examples.py"],
    # tests/test_reader_exports.py reaches no function of _long.py
    "sktiction/datasets/_long.py": [
        "tests/test_readers_long.py", "tests/test_read_loops.py",
        "tests/test_long_known_answers.py",
    ],
    # not the plant-window scan (51 s), nor the browser tests, nor the figures on two
    # processes or with a progress bar (their threads hang mutmut's forked runs)
    "sktiction/reports/valves.py": [
        "tests/test_reports_known_answers.py",
        *(f"tests/test_summarise_valves.py::{test}" for test in (
            "test_counts_shares_medians_and_verdicts_by_hand",
            "test_min_share_and_the_grouping_column", "test_awkward_reports_keep_every_record",
            "test_bad_input_is_named")),
        "tests/test_html_report.py::test_valves_with_several_records_are_summed_up_on_the_page",
        "tests/test_cli.py::test_console_and_html_pool_the_same_records_per_valve",
    ],
    "sktiction/reports/html.py": [
        "tests/test_reports_known_answers.py",
        *(f"tests/test_html_report.py::{test}" for test in (
            "test_file_is_self_contained",
            "test_a_loop_that_cannot_be_read_again_costs_only_its_figure",
            "test_report_rows_must_match_loops",
            "test_valves_with_several_records_are_summed_up_on_the_page",
            "test_a_scans_oscillation_columns_fill_the_table_for_every_loop")),
        "tests/test_reports.py::test_html_figure_titles_carry_the_verdict_and_sizes",
        "tests/test_cli.py::test_console_and_html_pool_the_same_records_per_valve",
    ],
    "sktiction/simulation/controllers.py": [
        "tests/test_simulation.py", "tests/test_valves.py", "tests/test_controllers.py",
    ],
    # not tests/test_common.py (a minute per mutant) nor the scans (the pretrained model)
    "sktiction/_validation.py": [
        "tests/test_gaps.py", "tests/test_features_loops.py",
        "tests/test_applicability.py::test_bad_input_is_refused_with_the_reason",
        "tests/test_scan_stream.py::test_gap_free_files_skip_repair_gaps_with_its_answer",
        "tests/test_cleaning.py::test_a_setpoint_with_a_hole_is_a_gap_not_a_missing_setpoint",
        "tests/test_validation_known_answers.py",
    ],
    "sktiction/simulation/effects.py": [
        "tests/test_simulation.py", "tests/test_effects_known_answers.py",
    ],
    "sktiction/simulation/disturbances.py": [
        "tests/test_simulation.py", "tests/test_disturbances_known_answers.py",
    ],
    "sktiction/simulation/plants.py": [
        "tests/test_simulation.py", "tests/test_controllers.py", "tests/test_valves.py",
        "tests/test_plants_known_answers.py",
    ],
    "sktiction/_cleaning.py": _CLEANING_TESTS,
    "sktiction/cycles/_repairs.py": [*_CLEANING_TESTS, "tests/test_cycles.py"],
    "sktiction/simulation/historian.py": [
        "tests/test_simulation.py", "tests/test_interpolated_exports.py",
        "tests/test_realism.py::test_statistics_separate_hold_compression_and_grid",
        "tests/test_historian_known_answers.py",
    ],
    # the four compare tests of tests/test_realism.py share a 4 s fixture (1,280 loops)
    "sktiction/realism/compare.py": [
        "tests/test_compare_known_answers.py",
        *(f"tests/test_realism.py::{test}"
          for test in ("test_compare_table_and_domain_auc",
                       "test_compare_reads_bunches_and_statistics",
                       "test_nothing_hidden_nothing_significant",
                       "test_hidden_effect_ranked_first")),
    ],
    # not the calibrate tests of tests/test_realism.py: an 8 s fixture (1,280 loops) and
    # pilots of 5-8 s; the known answers stand in a world of known answer for the pilot
    "sktiction/realism/calibrate.py": ["tests/test_calibrate_known_answers.py"],
}  # fmt: skip

# mutmut's exit codes (mutmut/stats.py)
_STATUS = {1: "killed", 3: "killed", 0: "survived", 5: "no tests", 33: "no tests",
           34: "skipped", 36: "timeout", 24: "timeout", -24: "timeout", 152: "timeout",
           255: "timeout", 37: "killed", None: "not checked"}  # fmt: skip
CAUGHT = ("killed", "timeout")
IGNORE = {".git", "mutants", "__pycache__", "build", ".hypothesis", ".pytest_cache"}


def _resolve(modules, tests):
    """Source globs and test paths for the modules asked for."""
    globs, default_tests = [], []
    for m in modules:
        if m in GROUPS:
            g, t = GROUPS[m]
        elif m in TARGETED:
            g, t = [m], TARGETED[m]
        else:
            g, t = [m], []
            for group_globs, group_tests in GROUPS.values():
                if any(Path(m).match(p) for p in group_globs):
                    t = group_tests
        globs += g
        default_tests += t
    tests = tests or default_tests
    if not tests:
        sys.exit(f"no tests known for {modules}; pass --tests")
    return list(dict.fromkeys(globs)), list(dict.fromkeys(tests))


def _copy_tree(workdir):
    """Scratch copy of the working tree (tracked and untracked files, as they are now)."""
    if workdir.exists():
        shutil.rmtree(workdir)

    def ignore(_dir, names):
        return [n for n in names if n in IGNORE or n.endswith(".egg-info")]

    shutil.copytree(ROOT, workdir, ignore=ignore)


def _configure(workdir, globs, tests):
    """Append mutmut's settings to the copy's pyproject.toml (the copy only)."""
    existing = [t for t in tests if (workdir / t.split("::")[0]).exists()]
    missing = sorted(set(tests) - set(existing))
    if missing:
        print(f"tests not in this tree, left out: {missing}")
    conf = {
        "source_paths": ["sktiction"],
        "also_copy": ["benchmarks"],  # some tests load a benchmark's helpers
        "only_mutate": globs,
        "pytest_add_cli_args_test_selection": existing,
        "pytest_add_cli_args": ["-p", "no:cacheprovider", "-x", "-q"],
    }
    lines = ["", "[tool.mutmut]"] + [f"{k} = {json.dumps(v)}" for k, v in conf.items()]
    with open(workdir / "pyproject.toml", "a", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")


def _run(workdir, max_children, log, names=()):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1",
               NUMBA_NUM_THREADS="1", PYTHONDONTWRITEBYTECODE="1")  # fmt: skip
    env.pop("PYTHONPATH", None)
    cmd = ["nice", "-n", "10", "mutmut", "run", "--max-children", str(max_children), *names]
    with open(log, "a", encoding="utf-8") as out:
        return subprocess.run(cmd, cwd=workdir, env=env, stdout=out, stderr=subprocess.STDOUT)


def _all_mutants(workdir):
    """Names of every mutant mutmut generated, in a stable order."""
    names = []
    for meta in sorted((workdir / "mutants").rglob("*.py.meta")):
        names += sorted(json.loads(meta.read_text())["exit_code_by_key"])
    return names


def _sample_run(workdir, max_children, log, size, seed, exclude=()):
    """Generate the mutants and the tests' coverage (a name that matches nothing stops
    mutmut right after), then run ``size`` of them drawn at random with ``seed`` from
    those not in ``exclude`` (an earlier sample whose survivors tests were written
    against: re-running it measures those tests, not the file)."""
    _run(workdir, max_children, log, ["no-such-mutant-only-generate"])
    names = [n for n in _all_mutants(workdir) if n not in set(exclude)]
    if not names:
        sys.exit(f"mutmut generated no mutants to draw from; see {log}")
    chosen = sorted(random.Random(seed).sample(names, min(size, len(names))))
    (workdir / "sample.json").write_text(json.dumps({"seed": seed, "of": len(names),
                                                     "names": chosen}))  # fmt: skip
    return _run(workdir, max_children, log, chosen)


def _recheck(workdir, globs, tests, max_children, log):
    """Run the last run's survivors again against the tree's current tests; keep the
    other verdicts (mutmut resets them when the test selection changes)."""
    metas = sorted((workdir / "mutants").rglob("*.py.meta"))
    before = {m: json.loads(m.read_text())["exit_code_by_key"] for m in metas}
    sample = _sample(workdir)
    names = [n for codes in before.values() for n, c in codes.items()
             if _STATUS.get(c, "suspicious") not in CAUGHT and c is not None
             and (sample is None or n in sample["names"])]  # fmt: skip
    print(f"rechecking {len(names)} survivors")
    for dest in (workdir / "tests", workdir / "mutants" / "tests"):
        shutil.copytree(ROOT / "tests", dest, dirs_exist_ok=True)
    shutil.copy2(ROOT / "pyproject.toml", workdir / "pyproject.toml")
    _configure(workdir, globs, tests)
    # which tests reach which function is collected again: mutmut would only add new tests
    # to it, not what edited ones reach now
    (workdir / "mutants" / "mutmut-stats.json").unlink(missing_ok=True)
    done = _run(workdir, max_children, log, names)
    for meta, codes in before.items():
        data = json.loads(meta.read_text())
        for name, code in codes.items():
            if name not in names:
                data["exit_code_by_key"][name] = code
        meta.write_text(json.dumps(data))
    return done


def _sample(workdir):
    path = workdir / "sample.json"
    return json.loads(path.read_text()) if path.exists() else None


def _wilson(k, n, z=1.96):
    """95 % Wilson score interval of a proportion k / n."""
    if n == 0:
        return 0.0, 1.0
    p, d = k / n, 1 + z * z / n
    mid, half = (p + z * z / (2 * n)) / d, z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return mid - half, mid + half


def _results(workdir, only=None):
    """{source file: Counter of statuses}, and the surviving mutant names (of ``only``,
    a sample's names, when given)."""
    per_file, survivors = {}, []
    for meta in sorted((workdir / "mutants").rglob("*.py.meta")):
        data = json.loads(meta.read_text())
        src = str(meta.relative_to(workdir / "mutants"))[: -len(".meta")]
        counts = Counter()
        for name, code in data["exit_code_by_key"].items():
            if only is not None and name not in only:
                continue
            status = _STATUS.get(code, "suspicious")
            counts[status] += 1
            if status not in CAUGHT:
                survivors.append((src, name, status))
        per_file[src] = counts
    return per_file, survivors


def _show(workdir, name):
    out = subprocess.run(["mutmut", "show", name], cwd=workdir, capture_output=True, text=True)
    return "\n".join(line for line in out.stdout.splitlines()
                     if line[:1] in "+-" and line[:3] not in ("+++", "---"))  # fmt: skip


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--module", nargs="+", default=["features"],
                   help="group names (see --list) or source files/globs to mutate")  # fmt: skip
    p.add_argument("--tests", nargs="+", default=None,
                   help="test files or node ids to run (default: the group's tests)")  # fmt: skip
    p.add_argument("--workdir", default="/tmp/sktiction-mutation", type=Path)
    p.add_argument("--max-children", default=1, type=int)
    p.add_argument("--list", action="store_true", help="print the groups and exit")
    p.add_argument("--report-only", action="store_true",
                   help="print the results of the last run in --workdir")  # fmt: skip
    p.add_argument("--sample", type=int, default=None,
                   help="run only this many mutants, drawn at random (see --seed)")  # fmt: skip
    p.add_argument("--seed", type=int, default=0, help="seed of --sample")
    p.add_argument("--exclude-sample", type=Path, default=None, metavar="WORKDIR",
                   help="an earlier sampled run: draw --sample from other mutants")  # fmt: skip
    p.add_argument("--recheck", action="store_true",
                   help="run the last survivors again against the current tests")  # fmt: skip
    args = p.parse_args(argv)
    if args.list:
        for name, (globs, tests) in GROUPS.items():
            print(f"{name}: {' '.join(globs)}\n    tests: {' '.join(tests)}")
        return 0
    if shutil.which("mutmut") is None:
        sys.exit("mutmut is not installed: pip install mutmut")
    globs, tests = _resolve(args.module, args.tests)
    workdir = args.workdir.resolve()
    if workdir == ROOT or ROOT in workdir.parents:
        sys.exit("--workdir must be outside the working tree")
    if args.recheck:
        _recheck(workdir, globs, tests, args.max_children, workdir / "mutmut.log")
    elif not args.report_only:
        print(f"mutating {globs}\nwith {tests}\nin {workdir}")
        _copy_tree(workdir)
        _configure(workdir, globs, tests)
        log = workdir / "mutmut.log"
        if args.sample:
            earlier = _sample(args.exclude_sample) if args.exclude_sample else {"names": ()}
            if earlier is None:
                sys.exit(f"no sample.json in {args.exclude_sample}")
            exclude = earlier["names"]
            done = _sample_run(workdir, args.max_children, log, args.sample, args.seed, exclude)
        else:
            done = _run(workdir, args.max_children, log)
        if done.returncode != 0:
            print(f"mutmut exited with {done.returncode}; see {log}")
    sample = _sample(workdir)
    if sample is not None:
        print(f"\na SAMPLE of {len(sample['names'])} of {sample['of']} mutants "
              f"(seed {sample['seed']})")  # fmt: skip
    per_file, survivors = _results(workdir, None if sample is None else set(sample["names"]))
    if not per_file:
        sys.exit(f"no results in {workdir / 'mutants'}")
    print(f"\n{'file':48s} {'mutants':>7s} {'killed':>6s} {'survived':>8s} {'no tests':>8s}"
          f" {'score':>6s}")  # fmt: skip
    for src, c in per_file.items():
        total = sum(c.values())
        caught = sum(c[s] for s in CAUGHT)
        print(f"{src:48s} {total:7d} {caught:6d} {c['survived']:8d} {c['no tests']:8d}"
              f" {caught / max(total, 1):6.1%}")  # fmt: skip
        if sample is not None:
            lo, hi = _wilson(caught, total)
            print(f"{'':48s} 95 % interval of the score: {lo:.1%} - {hi:.1%}")
    print("\nsurviving mutants (no test failed):")
    for _src, name, status in survivors:
        print(f"\n# {name} [{status}]\n{_show(workdir, name)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
