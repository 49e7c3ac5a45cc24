"""Generated from proto/lixel/v1/lixel.proto by the build (protoc and grpc_python_plugin)."""
