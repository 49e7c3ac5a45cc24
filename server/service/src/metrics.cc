// Prometheus metrics of the service.
#include <lixel/service/metrics.h>

#include <prometheus/text_serializer.h>

namespace lixel::service {

Metrics::Metrics(const std::string& address)
    : registry_(std::make_shared<prometheus::Registry>()) {
    requests_ = &prometheus::BuildCounter()
                     .Name("lixel_requests_total")
                     .Help("Requests answered, by RPC and gRPC status code")
                     .Register(*registry_);
    latency_ = &prometheus::BuildHistogram()
                    .Name("lixel_request_seconds")
                    .Help("Request latency in seconds, by RPC")
                    .Register(*registry_);
    queue_depth_ = &prometheus::BuildGauge()
                        .Name("lixel_queue_depth")
                        .Help("Tasks waiting for a worker")
                        .Register(*registry_)
                        .Add({});
    auto& maps = prometheus::BuildCounter()
                     .Name("lixel_maps_rendered_total")
                     .Help("Maps rendered (each pass counts)")
                     .Register(*registry_);
    maps_rendered_ = &maps.Add({});
    auto& bytes = prometheus::BuildCounter()
                      .Name("lixel_bytes_rendered_total")
                      .Help("Bytes of maps and masks rendered")
                      .Register(*registry_);
    bytes_rendered_ = &bytes.Add({});
    auto& cache = prometheus::BuildCounter()
                      .Name("lixel_scene_cache_lookups_total")
                      .Help("Scene cache lookups by result")
                      .Register(*registry_);
    cache_hits_ = &cache.Add({{"result", "hit"}});
    cache_misses_ = &cache.Add({{"result", "miss"}});
    cache_bytes_ = &prometheus::BuildGauge()
                        .Name("lixel_scene_cache_bytes")
                        .Help("Bytes held by the scene cache")
                        .Register(*registry_)
                        .Add({});
    auto& frames = prometheus::BuildCounter()
                       .Name("lixel_session_frames_total")
                       .Help("Session frames, by outcome (served or skipped)")
                       .Register(*registry_);
    session_frames_ = &frames.Add({{"outcome", "served"}});
    session_frames_skipped_ = &frames.Add({{"outcome", "skipped"}});
    auto& trees = prometheus::BuildCounter()
                      .Name("lixel_session_object_trees_total")
                      .Help(
                          "Session plans by what they did with the session's object tree: "
                          "build, refit or busy")
                      .Register(*registry_);
    object_tree_builds_ = &trees.Add({{"use", "build"}});
    object_tree_refits_ = &trees.Add({{"use", "refit"}});
    object_tree_busy_ = &trees.Add({{"use", "busy"}});
    session_frame_seconds_ =
        &prometheus::BuildHistogram()
             .Name("lixel_session_frame_seconds")
             .Help("Session frame latency in seconds, from its arrival to its last message written")
             .Register(*registry_)
             .Add({}, prometheus::Histogram::BucketBoundaries{0.001, 0.003, 0.01, 0.03, 0.1, 0.3,
                                                              1.0, 3.0, 10.0});
    if (!address.empty()) {
        exposer_ = std::make_unique<prometheus::Exposer>(address);
        exposer_->RegisterCollectable(registry_);
    }
}

void Metrics::Request(const std::string& rpc, const std::string& code, double seconds) {
    requests_->Add({{"rpc", rpc}, {"code", code}}).Increment();
    static const prometheus::Histogram::BucketBoundaries kBuckets = {
        0.0001, 0.0003, 0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0};
    latency_->Add({{"rpc", rpc}}, kBuckets).Observe(seconds);
}

void Metrics::SessionFrame(double seconds) {
    session_frames_->Increment();
    session_frame_seconds_->Observe(seconds);
}

std::string Metrics::Serialize() const {
    return prometheus::TextSerializer().Serialize(registry_->Collect());
}

int Metrics::port() const {
    if (!exposer_) return 0;
    const auto ports = exposer_->GetListeningPorts();
    return ports.empty() ? 0 : ports.front();
}

}  // namespace lixel::service
