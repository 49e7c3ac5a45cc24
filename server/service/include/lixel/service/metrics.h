// The service's Prometheus metrics (DESIGN §8): requests by RPC and status, latency histograms,
// queue depth, maps and bytes rendered, scene cache hits. Exposed over HTTP when an address is
// given.
#pragma once

#include <prometheus/counter.h>
#include <prometheus/exposer.h>
#include <prometheus/gauge.h>
#include <prometheus/histogram.h>
#include <prometheus/registry.h>

#include <memory>
#include <string>

namespace lixel::service {

class Metrics {
public:
    // `address` like "127.0.0.1:9464"; empty: collected, not exposed.
    explicit Metrics(const std::string& address);

    void Request(const std::string& rpc, const std::string& code, double seconds);
    void QueueDepth(double depth) { queue_depth_->Set(depth); }
    void MapsRendered(double maps, double bytes) {
        maps_rendered_->Increment(maps);
        bytes_rendered_->Increment(bytes);
    }
    // A session's frame: served (its maps streamed, OK or refused) with its latency from
    // arrival to its last message written, or skipped (superseded while the client ran ahead).
    void SessionFrame(double seconds);
    void SessionFramesSkipped(double frames) { session_frames_skipped_->Increment(frames); }
    // What a session's plans did with its kept object tree (object_index.h): built it, refit it
    // to moved objects, or found it busy (a session's frames plan one at a time, so only a
    // spurious failure of std::mutex::try_lock could count one).
    void SessionObjectTrees(double builds, double refits, double busy) {
        object_tree_builds_->Increment(builds);
        object_tree_refits_->Increment(refits);
        object_tree_busy_->Increment(busy);
    }
    void CacheLookup(bool hit) { (hit ? cache_hits_ : cache_misses_)->Increment(); }
    void CacheBytes(double bytes) { cache_bytes_->Set(bytes); }

    // Text exposition of every metric (what the HTTP endpoint serves), for tests and logs.
    std::string Serialize() const;
    // The port the exposer bound, 0 when not exposed.
    int port() const;

private:
    std::shared_ptr<prometheus::Registry> registry_;
    std::unique_ptr<prometheus::Exposer> exposer_;
    prometheus::Family<prometheus::Counter>* requests_;
    prometheus::Family<prometheus::Histogram>* latency_;
    prometheus::Gauge* queue_depth_;
    prometheus::Counter* maps_rendered_;
    prometheus::Counter* bytes_rendered_;
    prometheus::Counter* cache_hits_;
    prometheus::Counter* cache_misses_;
    prometheus::Gauge* cache_bytes_;
    prometheus::Counter* session_frames_;
    prometheus::Counter* session_frames_skipped_;
    prometheus::Counter* object_tree_builds_;
    prometheus::Counter* object_tree_refits_;
    prometheus::Counter* object_tree_busy_;
    prometheus::Histogram* session_frame_seconds_;
};

}  // namespace lixel::service
