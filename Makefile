# The two commands of the README, and the steps they are made of.
.PHONY: demo test benchmark setup build clean

# make demo DURATION=10 PLATFORM=simulator, or DEMO_DURATION / DEMO_PLATFORM in the environment
# (the short names only from the command line: environments often hold an unrelated PLATFORM).
demo:
	DEMO_DURATION="$(if $(filter command line,$(origin DURATION)),$(DURATION),$(DEMO_DURATION))" \
	DEMO_PLATFORM="$(if $(filter command line,$(origin PLATFORM)),$(PLATFORM),$(DEMO_PLATFORM))" \
	bash tools/demo.sh

test:
	bash tools/run_tests.sh

benchmark:
	bash tools/benchmark.sh

setup:
	bash tools/setup.sh

build: setup
	bash tools/build.sh

clean:
	bash -c 'source tools/common.sh && rm -rf "$$WORKSPACE_DIR"'
