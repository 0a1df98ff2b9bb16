# The two commands of the README, and the steps they are made of.
.PHONY: demo test setup build clean

demo:
	bash tools/demo.sh

test:
	bash tools/run_tests.sh

setup:
	bash tools/setup.sh

build: setup
	bash tools/build.sh

clean:
	rm -rf .workspace
