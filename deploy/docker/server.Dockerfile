# pslam-server in a container. Build from the repository root:
#   docker build -f deploy/docker/server.Dockerfile -t pslam-server .
#   docker run -p 8080:8080 -v pslam-data:/var/lib/pslam pslam-server
# Stage 1 builds the server and the viewer; stage 2 carries only what runs.
FROM debian:12 AS build
WORKDIR /src
COPY deploy/bootstrap.sh deploy/bootstrap.sh
RUN apt-get update && apt-get install -y --no-install-recommends nodejs npm && deploy/bootstrap.sh
COPY . .
RUN cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DPSLAM_BUILD_TESTS=OFF -DPSLAM_BUILD_BENCHMARKS=OFF \
 && cmake --build build --target pslam-server pslam \
 && cd web && npm ci --no-audit --no-fund && npm run build

FROM debian:12-slim
RUN apt-get update && apt-get install -y --no-install-recommends \
      libsqlite3-0 libpq5 libhiredis0.14 zlib1g libbz2-1.0 libceres3 libopencv-core406 libopencv-imgproc406 libopencv-imgcodecs406 ca-certificates \
 && rm -rf /var/lib/apt/lists/* \
 && useradd --system --home /var/lib/pslam pslam && mkdir -p /var/lib/pslam && chown pslam /var/lib/pslam
COPY --from=build /src/build/bin/pslam-server /src/build/bin/pslam /usr/local/bin/
COPY --from=build /src/web/dist /usr/local/share/pslam/web
USER pslam
EXPOSE 8080
VOLUME /var/lib/pslam
# Beyond loopback the server demands tokens: pass them, or mount a config file.
ENTRYPOINT ["/usr/local/bin/pslam-server", "--listen", "0.0.0.0:8080", "--data", "/var/lib/pslam", "--web", "/usr/local/share/pslam/web"]
CMD ["--agent-token", "change-me-agent-token-0001", "--viewer-token", "change-me-viewer-token-0001"]
