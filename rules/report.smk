# The study report. Every figure is drawn by a rule of its own (one job per figure, or per test
# or terrain class for a family) from the tables into results/report/figures/, registered with
# report() so `snakemake --report` shows it too; the report job only embeds the files. No figure
# shows the weights (the page draws the weighted contributions from results/scores/contributions.csv);
# the printed decision tree (figure_tree, rules/tree.smk) letters its leaves and the report's table
# under it orders each leaf's engines by the weighted total, so a weight edit redraws no figure. The figure inputs (PLAN.figures,
# PLAN.lab_figure_tests, PLAN.report_figures ...) are in simpick.plan.report.

# Figure rules: light jobs (one Matplotlib figure each), code= PLAN.figure_code, the code version of
# scripts/figure.py, the same for every figure. It reaches the report package, templates included
# (simpick.codeversion), so a template or report-code edit redraws the figures as well as the report.


if PLAN.answer_source:

    rule figure_answer:
        """The first page's figure: per engine the per-run values of each real-data metric and the
        interval of its difference to the best engine, the practical margin shaded (the verdict's runs,
        or the DRIVE comparison's steps: PLAN.answer_tables)."""
        input:
            outcomes=PLAN.answer_tables()["outcomes"],
            metrics=PLAN.answer_tables()["metrics"],
        output:
            png=report(
                f"{PLAN.figures}/answer.png",
                caption="captions/answer.rst",
                category="Figures",
                subcategory="Verdict",
            ),
        log:
            "results/logs/figures/answer.log",
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=300,
            runtime=5,
        params:
            settings=PLAN.figure_params("figure_answer"),
            code=PLAN.figure_code("figure_answer"),
        script:
            "../scripts/figure.py"


rule figure_imu_stats:
    """One lab test: IMU mean and range per axis (paper Figures 7-8)."""
    input:
        trace_stats=PLAN.metrics_file("lab", "detail"),
        reference_stats=PLAN.metrics_file("lab", "detail"),
        runs=PLAN.metrics_file("lab", "runs"),
    output:
        png=report(
            f"{PLAN.figures}/imu_stats/{{lab_terrain}}/{{lab_motion}}.png",
            caption="captions/imu_stats.rst",
            category="Figures",
            subcategory="IMU statistics",
            labels={"test": "{lab_terrain}/{lab_motion}"},
        ),
    log:
        "results/logs/figures/imu_stats/{lab_terrain}/{lab_motion}.log",
    # its own wildcard names: a reference-only test's terrain is not one the study simulates
    wildcard_constraints:
        lab_terrain="|".join(re.escape(t) for t in dict.fromkeys(t for t, _ in PLAN.lab_figure_tests)),
        lab_motion="|".join(re.escape(m) for m in dict.fromkeys(m for _, m in PLAN.lab_figure_tests)),
    conda:
        "../envs/simpick.yaml"
    threads: 1
    resources:
        mem_mb=300,
        runtime=5,
    params:
        settings=PLAN.figure_params("figure_imu_stats"),
        code=PLAN.figure_code("figure_imu_stats"),
    script:
        "../scripts/figure.py"


rule figure_traces:
    """One lab test: every engine's IMU time series."""
    input:
        traces=PLAN.lab_test_traces,
        runs=PLAN.metrics_file("lab", "runs"),
    output:
        png=report(
            f"{PLAN.figures}/traces/{{terrain}}/{{motion}}.png",
            caption="captions/traces.rst",
            category="Figures",
            subcategory="Traces",
            labels={"test": "{terrain}/{motion}"},
        ),
    log:
        "results/logs/figures/traces/{terrain}/{motion}.log",
    conda:
        "../envs/simpick.yaml"
    threads: 1
    resources:
        mem_mb=400,
        runtime=5,
    params:
        settings=PLAN.figure_params("figure_traces"),
        code=PLAN.figure_code("figure_traces"),
    script:
        "../scripts/figure.py"


rule figure_paths:
    """Every lab test's top-down paths, and the table of where each run ended."""
    input:
        traces=PLAN.source_traces("lab"),
        runs=PLAN.metrics_file("lab", "runs"),
    output:
        png=report(f"{PLAN.figures}/paths.png", caption="captions/paths.rst", category="Figures", subcategory="Traces"),
        endpoints=f"{PLAN.figures}/endpoints.csv",
    log:
        "results/logs/figures/paths.log",
    conda:
        "../envs/simpick.yaml"
    threads: 1
    resources:
        mem_mb=400,
        runtime=5,
    params:
        # the engines, the strip geometry and commanded paths: the report's own slice of the config
        settings=PLAN.figure_params("figure_paths"),
        code=PLAN.figure_code("figure_paths"),
    script:
        "../scripts/figure.py"


rule figure_validation:
    """Yaw-rate gain against commanded yaw rate (w < 0: right turns; bars: min-max over start
    headings), every engine and the Coulomb gain."""
    input:
        validation_gains="results/validation/gains.csv",
    output:
        png=report(
            f"{PLAN.figures}/validation_gain.png",
            caption="captions/validation_gain.rst",
            category="Figures",
            subcategory="Analytic mechanics",
        ),
    log:
        "results/logs/figures/validation_gain.log",
    conda:
        "../envs/simpick.yaml"
    threads: 1
    resources:
        mem_mb=300,
        runtime=5,
    params:
        settings=PLAN.figure_params("figure_validation"),
        code=PLAN.figure_code("figure_validation"),
    script:
        "../scripts/figure.py"


rule figure_real_gain:
    """Yaw-rate gain per terrain class: the real robot against every model."""
    input:
        unpack(PLAN.real_gain_inputs),
    output:
        png=report(
            f"{PLAN.figures}/real_gain.png",
            caption="captions/real_gain.rst",
            category="Figures",
            subcategory="Real robot",
        ),
    log:
        "results/logs/figures/real_gain.log",
    conda:
        "../envs/simpick.yaml"
    threads: 1
    resources:
        mem_mb=300,
        runtime=5,
    params:
        settings=PLAN.figure_params("figure_real_gain"),
        code=PLAN.figure_code("figure_real_gain"),
    script:
        "../scripts/figure.py"


if PLAN.sweep:

    rule figure_sweep:
        """The speed-accuracy sweep: real-data error against real-time factor per timestep."""
        input:
            sweep=f"{PLAN.sweep_dir}/summary.csv",
        output:
            png=report(
                f"{PLAN.figures}/sweep.png",
                caption="captions/sweep.rst",
                category="Figures",
                subcategory="Speed and accuracy",
            ),
        log:
            "results/logs/figures/sweep.log",
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=300,
            runtime=5,
        params:
            settings=PLAN.figure_params("figure_sweep"),
            code=PLAN.figure_code("figure_sweep"),
        script:
            "../scripts/figure.py"


if PLAN.replay_set:

    rule figure_real_turning:
        """The real robot's yaw-rate gain against speed, turn radius and wheel-speed difference."""
        input:
            windows=f"{PLAN.replay}/turning/windows.csv",
        output:
            png=report(
                f"{PLAN.figures}/real_turning.png",
                caption="captions/real_turning.rst",
                category="Figures",
                subcategory="Real robot",
            ),
        log:
            "results/logs/figures/real_turning.log",
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=300,
            runtime=5,
        params:
            settings=PLAN.figure_params("figure_real_turning"),
            code=PLAN.figure_code("figure_real_turning"),
        script:
            "../scripts/figure.py"

    rule figure_replay:
        """One terrain class of the full replay: a representative run against every model, and the
        mean vertical-acceleration spectra; the notes say which run and why."""
        input:
            unpack(PLAN.replay_class_inputs),
        output:
            png=report(
                f"{PLAN.figures}/replay/{{terrain_class}}.png",
                caption="captions/replay.rst",
                category="Figures",
                subcategory="Real robot",
                labels={"terrain class": "{terrain_class}"},
            ),
            notes=f"{PLAN.figures}/replay/{{terrain_class}}.json",
        log:
            f"results/logs/figures/replay/{{terrain_class}}.log",
        wildcard_constraints:
            terrain_class="|".join(PLAN.replay_set.classes),
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=800,
            runtime=10,
        params:
            settings=PLAN.figure_params("figure_replay"),
            code=PLAN.figure_code("figure_replay"),
        script:
            "../scripts/figure.py"


# The evidence's sections 2-5 (qualitative features; speed, CPU load and IMU error; analytic mechanics; the
# real robot's data) and the appendices (the raw tables), which no weight reaches: a job of their own
# renders them, an HTML fragment and a PDF (evidence.html.j2), from the report's inputs less the weighted
# tables and the answer's, the per-metric scores beside the figures from the scores job (no weight), the
# engines in the study's order, so that a weight edit does not lay them out again. The report job places the
# fragment after section 1 of the evidence and joins the PDFs (simpick.report.pdf): the user gets one
# report.html and one report.pdf.
rule report_evidence:
    input:
        unpack(PLAN.evidence_real_inputs),
        scores="results/scores/scores.csv",
        scores_provenance="results/scores/provenance.yaml",
        validation="results/validation/summary.csv",
        validation_gains="results/validation/gains.csv",
        trace_stats=PLAN.metrics_file("lab", "detail"),
        reference_stats=PLAN.metrics_file("lab", "detail"),
        imu_errors=PLAN.metrics_file("lab", "imu_errors"),
        per_test_errors=PLAN.metrics_file("lab", "detail"),
        runs=PLAN.metrics_file("lab", "runs"),
        rtf=PLAN.metrics_file("lab", "rtf"),
        cpu=expand("results/cpu/{engine}.json", engine=PLAN.engines),
        qualitative=SETTINGS.qualitative,
        table11="results/published/table11.csv",
        table11_comparison="results/published/table11_comparison.csv",
        worked_example="results/published/worked_example.json",
        figures=PLAN.evidence_figures(),
        endpoints=f"{PLAN.figures}/endpoints.csv",
    output:
        html="results/report/parts/evidence.html",
        pdf="results/report/parts/evidence.pdf",
    log:
        "results/logs/report_evidence.log",
    benchmark:
        "results/benchmarks/report_evidence.tsv"
    conda:
        "../envs/simpick.yaml"
    resources:
        mem_mb=800,
        runtime=10,
    params:
        # the report's slice of the config, the statistics, the engines in the study's order (no ranking) and
        # the real data's settings: no weight
        settings=PLAN.evidence_params(),
        code=PLAN.script_code("report_evidence"),
    script:
        "../scripts/report_evidence.py"


# The report job first weighs the scores (the weighted tables, the answer where the study has real data of
# its robot, and the simulators' weighted table: simpick.report.weighing), which no other job reads before
# it, then writes the page: a weight edit reruns this job alone.
rule report:
    input:
        unpack(PLAN.report_real_inputs),
        # what the weighing reads, named weighing_* (PLAN.weighing_inputs)
        unpack(PLAN.weighing_inputs),
        # the decision tree's data: the page's interactive section answers it (rules/tree.smk)
        tree="results/verdict/tree.json",
        scores_provenance="results/scores/provenance.yaml",
        validation="results/validation/summary.csv",
        validation_gains="results/validation/gains.csv",
        # the lab's per-axis table holds the simulated statistics, the paper's and the errors between
        trace_stats=PLAN.metrics_file("lab", "detail"),
        reference_stats=PLAN.metrics_file("lab", "detail"),
        imu_errors=PLAN.metrics_file("lab", "imu_errors"),
        per_test_errors=PLAN.metrics_file("lab", "detail"),
        runs=PLAN.metrics_file("lab", "runs"),
        rtf=PLAN.metrics_file("lab", "rtf"),
        cpu=expand("results/cpu/{engine}.json", engine=PLAN.engines),
        qualitative=SETTINGS.qualitative,
        table11="results/published/table11.csv",
        table11_comparison="results/published/table11_comparison.csv",
        worked_example="results/published/worked_example.json",
        # the first page's figures, embedded (the report draws nothing itself; the others are the evidence's)
        figures=PLAN.body_figures(),
        endpoints=f"{PLAN.figures}/endpoints.csv",
        # the DRIVE comparison and turn map (--config drive_dir=PATH): the verdict against the real robot
        drive=[f"{DRIVE}/{t}.csv" for t in ("summary", "outcomes", "turning", "errors")] if SETTINGS.drive_dir else [],
        # with calibration.enabled: the held-out multipliers (simpick.studies.calibration.steps)
        drive_calibration=(
            [f"{DRIVE}/calibration/turning.csv"]
            if SETTINGS.drive_dir and SETTINGS.calibration and SETTINGS.calibration.enabled
            else []
        ),
        turnmap=TURNMAP_TARGETS,
        # the simulators as rows (rules/simulators.smk), when the study runs any
        simulators=(
            [
                "results/simulators/table.csv",
                "results/simulators/per_class.csv",
                "results/simulators/tree.json",
                "results/simulators/settings",
                # the models that open as they are, which the simulators' section links to
                *([PLAN.MODELS_DIR] if PLAN.model_profiles else []),
            ]
            if PLAN.simulators
            else []
        ),
        # the evidence's sections 2-5 and the appendices, rendered by rule report_evidence: placed after
        # section 1 of the evidence, their PDF joined
        evidence_html="results/report/parts/evidence.html",
        evidence_pdf="results/report/parts/evidence.pdf",
    output:
        **{
            name: report(path, caption=caption, category=category)
            for name, (path, caption, category) in PLAN.weighing_outputs().items()
        },
        # report(): `snakemake --report` carries the study report (its figures are embedded in it).
        # The HTML and its PDF in one job: one process start and one context less on every rerun;
        # the PDF lays out the body alone and joins the evidence's PDF after it.
        html=report("results/report/report.html", caption="captions/report_html.rst", category="Study report"),
        pdf=report("results/report/report.pdf", caption="captions/report_pdf.rst", category="Study report"),
        # the weighing's tables (PLAN.weighing_outputs)
    log:
        "results/logs/report.log",
    benchmark:
        "results/benchmarks/report.tsv"
    conda:
        "../envs/simpick.yaml"
    # the PDF's body is laid out in two parts at once (simpick.report.pdf.split_body); fewer cores: one by one
    threads: 2
    params:
        # the weights, and only the keys of the config the report reads (strip geometry, commanded paths, test
        # order, the real data's settings): an edit elsewhere reaches it through its inputs or not at all; the
        # configured engines this machine cannot run (listed, not dropped) and the registered engines an opt-in
        # config adds (named as not run, with the switch)
        settings=PLAN.report_params(),
        weighing=PLAN.weighing_params(),
        code=PLAN.script_code("report"),
        # the DRIVE tables' folder (results/drive/<name>), from the inputs: empty without drive_dir
        drive=lambda wildcards, input: os.path.dirname(input.drive[0]) if input.drive else "",
        drive_calibration=lambda wildcards, input: input.drive_calibration[0] if input.drive_calibration else "",
        # the simulators' folder, from the inputs: empty when the study runs none
        simulators=lambda wildcards, input: os.path.dirname(input.simulators[0]) if input.simulators else "",
    script:
        "../scripts/report.py"
