# The benchmark across robots: snakemake -s rules/robots.smk --cores 2 (docs/robots.md).
# Each robot of config/robots.yaml runs the project's Snakefile as a Snakemake module (`module` /
# `use rule * from`), its config built by simpick.config.robots (config.yaml, the robot's config files, its
# settings), its rules named <robot>_<rule>. The module's paths under results/ move to results/robots/<robot>/
# (replace_prefix): a plain `prefix` would move every relative input too, resources/ and the robot's URDF
# among them, to where no file is; ../shared and absolute paths are never moved. Each module parses the
# Snakefile with its own globals (its PLAN, SETTINGS, DRIVE ...) and its own checkpoints, so two robots'
# plans do not meet. The page reads each robot's public outputs only: its answer (results/verdict/answer.csv,
# headline.yaml) and its simulators' table (results/simulators/table.csv).
import os

from snakemake.utils import min_version

from simpick.codeversion import job_code, script_roots
from simpick.config.robots import benchmark, robots_params
from simpick.errors import InputError

min_version("9.0")


configfile: "config/robots.yaml"


# the project's folder (scripts/); config files, data and results are relative to the working directory, as
# for a study of its own (its config.yaml is the one every robot's config starts from)
ROOT = os.path.dirname(workflow.current_basedir.get_path_or_uri(secret_free=True))
try:
    ROBOTS, POOLING = benchmark(config, ".", source="config/robots.yaml")
except InputError as _exc:
    raise WorkflowError(str(_exc))


def robot_results(robot):
    """Where a robot's study writes what its own study writes under results/."""
    return f"results/robots/{robot}"


for robot, study in ROBOTS.items():
    robot_prefix = f"{robot}_"

    module:
        name: robot
        snakefile:
            "../Snakefile"
        config:
            study.config
        replace_prefix:
            {"results/": f"{robot_results(robot)}/"}

    use rule * from robot as robot_prefix*

    # the page compares the robots' answers (each study's report job writes its answer): a study without real
    # data of its robot plans none
    if not any(str(f).endswith("verdict/answer.csv") for f in workflow.get_rule(f"{robot}_report").output):
        raise WorkflowError(
            f"config/robots.yaml, robots.{robot}: its study has no real data of this robot, so no answer to set "
            "beside the others (fix: give it its data in config, drive_dir, borealtc_dir or own_logs, or leave "
            "it out of the list)"
        )


rule robots:
    """The robots side by side (simpick.score.robots) and the page (simpick.report.robots)."""
    default_target: True
    input:
        answers=[f"{robot_results(r)}/verdict/answer.csv" for r in ROBOTS],
        headlines=[f"{robot_results(r)}/verdict/headline.yaml" for r in ROBOTS],
        simulators=[f"{robot_results(r)}/simulators/table.csv" for r in ROBOTS],
        # the settings files each robot's simulators' answer links to
        settings=[f"{robot_results(r)}/simulators/settings" for r in ROBOTS],
    output:
        table="results/robots/benchmark.csv",
        agreement="results/robots/agreement.csv",
        html="results/robots/benchmark.html",
        pdf="results/robots/benchmark.pdf",
    log:
        "results/logs/robots.log",
    conda:
        "../envs/simpick.yaml"
    params:
        # the robots in order (name, label, command, settings, files) and the pooling: rule robots' job's model
        # (simpick.report.robots.RobotsParams)
        settings=robots_params(ROBOTS, POOLING),
        code=job_code(*script_roots(os.path.join(ROOT, "scripts", "robots.py"))),
    script:
        "../scripts/robots.py"
