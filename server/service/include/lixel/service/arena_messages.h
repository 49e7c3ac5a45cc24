// One protobuf arena per unary call for its request and response (gRPC's MessageAllocator). A
// Plan request's objects are four messages and a string each; on the heap, parsing 10 000 of
// them took as long as planning them and freeing them as long again. In an arena every message
// of the call comes from a few large blocks, and the arena frees them at once when the call ends.
#pragma once

#include <google/protobuf/arena.h>
#include <grpcpp/support/message_allocator.h>

#include <cstddef>

namespace lixel::service {

template <class Request, class Response>
class ArenaMessages final : public grpc::MessageAllocator<Request, Response> {
  public:
    grpc::MessageHolder<Request, Response>* AllocateMessages() override { return new Holder; }

  private:
    // Blocks grow from 1 KiB (a small request fits its first) to 64 KiB, so a large request
    // takes tens of allocations where it took tens of thousands.
    static google::protobuf::ArenaOptions Options() {
        google::protobuf::ArenaOptions options;
        options.start_block_size = 1024;
        options.max_block_size = 64 * 1024;
        return options;
    }

    class Holder final : public grpc::MessageHolder<Request, Response> {
      public:
        Holder() : arena_(Options()) {
            this->set_request(google::protobuf::Arena::CreateMessage<Request>(&arena_));
            this->set_response(google::protobuf::Arena::CreateMessage<Response>(&arena_));
        }
        void Release() override { delete this; }

      private:
        google::protobuf::Arena arena_;
    };
};

}  // namespace lixel::service
