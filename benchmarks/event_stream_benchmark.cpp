// What the event stream costs the sequencer's thread (the thread that drains the capture ring):
// Publish of a progress event to a reader that keeps up (/dev/null) and to one that has stopped (a
// full pipe: the drop path), and the live plot's share of one ring drain at 100 kHz (2000 samples,
// one 20 ms loop period) with a 100 s run's decimation. Google Benchmark; run by hand.
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "hrgbench/bench/events/event_stream.hpp"
#include "hrgbench/bench/events/session_events.hpp"

namespace {

using namespace hrgbench::bench;

nlohmann::json ProgressEvent(std::int64_t i) {
  return {{"type", "progress"}, {"run", 2},
          {"run_count", 6},     {"run_id", 2},
          {"phase", "capture"}, {"samples", i},
          {"elapsed_s", 1.5},   {"remaining_s", 300.0},
          {"samples_lost", 0},  {"table_rate_rad_s", 0.9999}};
}

void PublishToAReaderThatKeepsUp(benchmark::State& state) {
  auto stream =
      EventStream::FromFd(::open("/dev/null", O_WRONLY | O_CLOEXEC), EventStream::kDefaultCapacity);
  std::int64_t i = 0;
  for (auto _ : state) stream->Publish(ProgressEvent(i++));
  const EventStreamStats stats = stream->Close(10'000);
  state.counters["lost"] = static_cast<double>(stats.lost);
}
BENCHMARK(PublishToAReaderThatKeepsUp);

void PublishToAStoppedReader(benchmark::State& state) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return state.SkipWithError("pipe");
  ::fcntl(fds[1], F_SETFL, ::fcntl(fds[1], F_GETFL) | O_NONBLOCK);
  const std::string block(4096, 'x');
  while (::write(fds[1], block.data(), block.size()) > 0) {
  }
  ::fcntl(fds[1], F_SETFL, ::fcntl(fds[1], F_GETFL) & ~O_NONBLOCK);
  auto stream = EventStream::FromFd(fds[1], EventStream::kDefaultCapacity);
  std::int64_t i = 0;
  for (auto _ : state) stream->Publish(ProgressEvent(i++));
  const EventStreamStats stats = stream->Close(0);
  state.counters["lost"] = static_cast<double>(stats.lost);
  ::close(fds[0]);
}
BENCHMARK(PublishToAStoppedReader);

void LivePlotShareOfOneDrain(benchmark::State& state) {
  auto stream =
      EventStream::FromFd(::open("/dev/null", O_WRONLY | O_CLOEXEC), EventStream::kDefaultCapacity);
  SessionEventPublisher publisher(*stream);
  BenchConfigs configs;
  SequenceRun run;
  run.free_run_s = 100.0;
  run.sample_rate_hz = 100000;  // 10 M samples: a stride of 25 000
  configs.sequence.runs = {run};
  publisher.SessionStarted(configs, "SN", "dir", false, "bench");
  RunnerOptions options;
  publisher.Attach(options);
  std::vector<GyroSampleRecord> batch(2000);  // one 20 ms loop period at 100 kHz
  for (auto _ : state) options.on_samples(1, batch);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(batch.size()));
  stream->Close(10'000);
}
BENCHMARK(LivePlotShareOfOneDrain);

}  // namespace

int main(int argc, char** argv) {
  ::signal(SIGPIPE, SIG_IGN);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
