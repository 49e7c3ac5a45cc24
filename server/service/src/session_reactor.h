// The Session RPC's reactor (docs/service.md, "Sessions"): a bidirectional stream that reads
// frames as they come (SessionState), runs them one at a time on the work pool through Render's
// job, and writes each frame's header, chunks and done in frame order, one write at a time.
// Frames more than max_frames_ahead ahead of the one rendering are skipped with a notice; a
// client that stops reading is ended after stream_idle_seconds (its frame's job stalls).
#pragma once

#include <grpcpp/grpcpp.h>
#include <lixel/service/shadow_service.h>
#include <lixel/v1/lixel.grpc.pb.h>

namespace lixel::service {

grpc::ServerBidiReactor<v1::SessionRequest, v1::SessionResponse>* NewSessionReactor(
    ShadowService& service, grpc::CallbackServerContext* context);

}  // namespace lixel::service
