# The scores, which read no weight, and results/scores/provenance.yaml: which errors file, tests and
# exclusions they rest on (the report reads that file rather than working it out from the config
# again). The weights reach the weighted table only: rule answer (or rule weighted, without an answer) weighs the scores,
# so that a weight edit reruns neither the scores nor what reads them alone (the report's evidence and
# appendices, rule report_evidence).
rule scores:
    input:
        imu_errors=PLAN.accuracy_errors(),
        accuracy_tests=PLAN.accuracy_source()["per_test"],
        runs=PLAN.metrics_file("lab", "runs"),
        rtf=PLAN.metrics_file("lab", "rtf"),
        cpu=expand("results/cpu/{engine}.json", engine=PLAN.engines),
        qualitative=SETTINGS.qualitative,
    output:
        scores=report("results/scores/scores.csv", caption="captions/scores.rst", category="Scores"),
        provenance=report("results/scores/provenance.yaml", caption="captions/scores_provenance.rst", category="Scores"),
    log:
        "results/logs/scores.log",
    benchmark:
        "results/benchmarks/scores.tsv"
    conda:
        "../envs/simpick.yaml"
    threads: 1
    resources:
        mem_mb=300,
        runtime=5,
    params:
        engines=sorted(PLAN.engines),  # a reordered engines: block is not an edit
        accuracy=canonical({k: PLAN.accuracy_source()[k] for k in ("reference", "set", "dataset")}),
        cpu_test=f"{SETTINGS.cpu_load.terrain}/{SETTINGS.cpu_load.motion}",
        code=PLAN.script_code("scores"),
    script:
        "../scripts/scores.py"


# The weighted table: the scores times the config's weights, the totals and the ranking, and per engine
# and metric its weight x score and what puts the leader ahead of each engine. All a weight edit reruns
# of the scores. Where the study has an answer (real data of its robot), rule answer writes these tables
# itself, as it reads them: one level of jobs (a process start and a scheduling step) less on the weight
# path, [answer, simulator_scores] -> report. Without one, a job of their own.
if not PLAN.answer_source:

    rule weighted:
        input:
            scores="results/scores/scores.csv",
        output:
            weighted=report("results/scores/weighted.csv", caption="captions/weighted.rst", category="Scores"),
            contributions=report(
                "results/scores/contributions.csv", caption="captions/scores_contributions.rst", category="Scores"
            ),
            drivers=report("results/scores/drivers.csv", caption="captions/scores_contributions.rst", category="Scores"),
        log:
            "results/logs/weighted.log",
        benchmark:
            "results/benchmarks/weighted.tsv"
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=300,
            runtime=5,
        params:
            weights=canonical(SETTINGS.weights),
            code=PLAN.script_code("weighted"),
        script:
            "../scripts/weighted.py"


# simpick's verdict beside the paper's method (simpick.score.verdict): per real run the yaw-rate gain
# error, the heading error and (where a log measures it) the speed error, with intervals; every engine
# against the best (outcomes.csv: worse, equivalent within the config's margin, or undetermined;
# simpick.score.equivalence) behind the mechanics gate of the validation (mechanics.csv); what the
# paper's accuracy scores separate. It reads no weight: a weight edit does not rerun these tests, a
# margin edit reruns them and the answer, not the scores.
if PLAN.verdict:

    rule verdict:
        input:
            per_test=PLAN.metrics_file(PLAN.verdict_source(), "per_test"),
            accuracy_tests=PLAN.accuracy_source()["per_test"],
            accuracy_errors=PLAN.accuracy_errors(),
            validation="results/validation/summary.csv",
        output:
            metrics=report("results/verdict/metrics.csv", caption="captions/verdict_metrics.rst", category="Verdict"),
            table=report("results/verdict/table.csv", caption="captions/verdict_table.rst", category="Verdict"),
            outcomes=report("results/verdict/outcomes.csv", caption="captions/verdict_outcomes.rst", category="Verdict"),
            mechanics=report(
                "results/verdict/mechanics.csv", caption="captions/verdict_mechanics.rst", category="Verdict"
            ),
            discrimination=report(
                "results/verdict/discrimination.csv", caption="captions/verdict_discrimination.rst", category="Verdict"
            ),
            headings=report("results/verdict/headings.csv", caption="captions/verdict_headings.rst", category="Verdict"),
        log:
            "results/logs/verdict.log",
        benchmark:
            "results/benchmarks/verdict.tsv"
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=500,
            runtime=10,
        params:
            settings=PLAN.verdict_settings(),
            code=PLAN.script_code("verdict"),
        script:
            "../scripts/verdict.py"


# The answer (simpick.score.answer): one row per engine and a sentence per need, the paper's
# weighted total with its interval over real runs, the separation table and the report's first
# paragraph, and the weighted table with its contributions and drivers (simpick.score.jobs.weigh). The
# weights reach it: it is what a weight edit reruns besides the simulators' weighted table and the report, kept small (a resampled total, no test). It rests on the real data the study has of its
# robot (PLAN.answer_tables): the verdict's runs above, else the DRIVE comparison's steps
# (rules/drive.smk, which writes the same tables beside its outcomes).
if PLAN.answer_source:

    rule answer:
        input:
            unpack(PLAN.answer_inputs),
            accuracy_tests=PLAN.accuracy_source()["per_test"],
            # weighed here (the tables rule weighted writes without an answer), not read
            scores="results/scores/scores.csv",
            provenance="results/scores/provenance.yaml",
            rtf=PLAN.metrics_file("lab", "rtf"),
            cpu=expand("results/cpu/{engine}.json", engine=PLAN.engines),
        output:
            ranking=report("results/verdict/ranking.csv", caption="captions/verdict_ranking.rst", category="Verdict"),
            separation=report(
                "results/verdict/separation.csv", caption="captions/verdict_separation.rst", category="Verdict"
            ),
            answer=report("results/verdict/answer.csv", caption="captions/verdict_answer.rst", category="Verdict"),
            answer_yaml=report("results/verdict/answer.yaml", caption="captions/verdict_answer.rst", category="Verdict"),
            headline=report(
                "results/verdict/headline.yaml", caption="captions/verdict_headline.rst", category="Verdict"
            ),
            weighted=report("results/scores/weighted.csv", caption="captions/weighted.rst", category="Scores"),
            contributions=report(
                "results/scores/contributions.csv", caption="captions/scores_contributions.rst", category="Scores"
            ),
            drivers=report("results/scores/drivers.csv", caption="captions/scores_contributions.rst", category="Scores"),
        log:
            "results/logs/answer.log",
        benchmark:
            "results/benchmarks/answer.tsv"
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=400,
            runtime=5,
        params:
            settings=PLAN.answer_settings(),
            code=PLAN.script_code("answer"),
        script:
            "../scripts/answer.py"
