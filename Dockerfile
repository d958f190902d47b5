# syntax=docker/dockerfile:1
# bearing-sim service image: a locked release build, run as a non-root user on a
# distroless base; the SQLite database lives in the /data volume.

FROM rust:1.95-bookworm AS build
WORKDIR /src
COPY Cargo.toml Cargo.lock build.rs ./
COPY src ./src
# The engine crate (a workspace member; its manifest declares a bench, so that source
# comes along).
COPY crates ./crates
COPY migrations ./migrations
# --locked: exactly the dependency versions of Cargo.lock, as CI builds them.
RUN --mount=type=cache,target=/usr/local/cargo/registry \
    --mount=type=cache,target=/src/target \
    cargo build --release --locked --bin bearing-sim \
    && cp target/release/bearing-sim /bearing-sim \
    && mkdir /data

FROM gcr.io/distroless/cc-debian12:nonroot
COPY --from=build /bearing-sim /usr/local/bin/bearing-sim
COPY --from=build --chown=65532:65532 /data /data
# The container listens on every interface, so it requires API tokens: mount a tokens
# file (lines from `bearing-sim token NAME`) at /run/secrets/bearing-sim-tokens, or set
# BEARING_SIM_TOKENS_FILE= (empty) to run open, with a warning (docs/reference/operations.md).
# The variable holds the file's path, not a secret (hadolint matches its name).
# hadolint ignore=DL3064
ENV BEARING_SIM_BIND=0.0.0.0:8080 \
    BEARING_SIM_DATABASE_URL=sqlite:///data/bearing-sim.db \
    BEARING_SIM_TOKENS_FILE=/run/secrets/bearing-sim-tokens \
    BEARING_SIM_LOG_FORMAT=json
USER 65532:65532
VOLUME ["/data"]
EXPOSE 8080
# The binary probes its own /healthz: the image has no shell or curl.
HEALTHCHECK --interval=15s --timeout=5s --start-period=10s --retries=3 \
    CMD ["/usr/local/bin/bearing-sim", "serve", "--probe"]
ENTRYPOINT ["/usr/local/bin/bearing-sim"]
CMD ["serve"]
