# The two commands of the README, and the steps they are made of.
.PHONY: demo test benchmark soak gesture-race motion-report setup build clean

# make demo DURATION=10 PLATFORM=simulator BEHAVIOUR=hands OUTPUT_DIR=/tmp/demo GESTURE=1
#           STYLE=breathing DRIVER=naoqi_dcm NODE_ARGS="_gestureDuration:=1.5" SIM_ARGS="..." INTERACTION=1
#           ACTUATION=joint_angles CONVERSATION=1 ROS=2   (ROS=2: the same demo on ROS 2, tools/demo_ros2.sh)
#           ROBOTS=2   (two robots in robot1 and robot2, one plot of both)
# or DEMO_DURATION, DEMO_PLATFORM, ... in the environment (the short names only from the command line:
# environments often hold an unrelated PLATFORM).
DEMO_OPTIONS := DURATION PLATFORM BEHAVIOUR OUTPUT_DIR GESTURE STYLE DRIVER NODE_ARGS SIM_ARGS INTERACTION ACTUATION ROS ROBOTS CONVERSATION
demo:
	$(foreach option,$(DEMO_OPTIONS),$(if $(filter command line,$(origin $(option))),DEMO_$(option)='$(subst ','\'',$($(option)))')) \
	bash tools/demo.sh

test:
	bash tools/run_tests.sh

# make benchmark CYCLES=30 CPU_WINDOW=20 EXIT_RUNS=3 PLATFORMS="robot simulator" JSON=/tmp/b.json
#                SOAK=3600 GROWTH_CYCLES=10000 PYTHON38=1 ROS=1|2 DOMAIN_ID=42 (or BENCHMARK_CYCLES, ... in the
#                environment): doc/performance.md.
BENCHMARK_OPTIONS := CYCLES CPU_WINDOW EXIT_RUNS PLATFORMS JSON SOAK GROWTH_CYCLES PYTHON38 ROS DOMAIN_ID
benchmark:
	$(foreach option,$(BENCHMARK_OPTIONS),$(if $(filter command line,$(origin $(option))),BENCHMARK_$(option)='$(subst ','\'',$($(option)))')) \
	bash tools/benchmark.sh

# make soak DURATION=60 WARM_UP=10 ROS=1|2 SEED=1 TRACEMALLOC=1 SIM_CLOCK=0 (or SOAK_DURATION, ... in the environment): doc/soak.md.
SOAK_OPTIONS := DURATION WARM_UP ROS SEED TRACEMALLOC SIM_CLOCK
soak:
	$(foreach option,$(SOAK_OPTIONS),$(if $(filter command line,$(origin $(option))),SOAK_$(option)='$(subst ','\'',$($(option)))')) \
	bash tools/soak.sh

# make gesture-race ROS=1|2 GESTURES=100 STYLE=random|breathing SEED=1 RESEND=1 (or RACE_ROS, ...): doc/soak.md.
RACE_OPTIONS := ROS GESTURES STYLE SEED RESEND
gesture-race:
	$(foreach option,$(RACE_OPTIONS),$(if $(filter command line,$(origin $(option))),RACE_$(option)='$(subst ','\'',$($(option)))')) \
	bash tools/gesture_race.sh

# What a person sees of each motion style: ideal, through pepper_dcm, through joint_angles (README: "Motion styles").
motion-report:
	bash tools/motion_report.sh

setup:
	bash tools/setup.sh

build: setup
	bash tools/build.sh

clean:
	bash -c 'source tools/common.sh && rm -rf "$$WORKSPACE_DIR"'
