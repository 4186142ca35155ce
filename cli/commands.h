#pragma once
#include <functional>

#include <CLI/CLI.hpp>

namespace facesr::cli {

// Each register_* adds a subcommand and records the action to run when it is
// the one selected; actions throw facesr::Error on bad input.
void register_rig(CLI::App& app);
void register_head(CLI::App& app);
void register_devices(CLI::App& app);
void register_render(CLI::App& app);
void register_perf(CLI::App& app);
void register_simulate(CLI::App& app);
void register_bench(CLI::App& app);
void register_dataset(CLI::App& app);
void register_train(CLI::App& app);
void register_eval(CLI::App& app);
void register_play(CLI::App& app);
void register_model(CLI::App& app);
void register_character(CLI::App& app);
// `bench runtime`, under the `bench` group that register_bench makes.
void add_bench_runtime(CLI::App* bench);
void add_bench_contexts(CLI::App* bench);
void add_action(CLI::App* sub, std::function<void()> action);
void run_selected(CLI::App& app);

}  // namespace facesr::cli
