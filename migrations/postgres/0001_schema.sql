-- The PostgreSQL schema: the same tables and columns as the SQLite migrations reach
-- (migrations/sqlite/0001-0003), in one step. JSON is kept as text, verbatim, so both
-- backends count stored bytes alike; times are unix milliseconds.
CREATE TABLE jobs (
    seq               BIGINT  GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
    id                TEXT    NOT NULL UNIQUE,
    tenant            TEXT    NOT NULL DEFAULT '',    -- API token name ('' without tokens)
    kind              TEXT    NOT NULL,               -- simulation | analysis
    state             TEXT    NOT NULL,               -- queued | running | succeeded | failed | cancelled
    input             TEXT    NOT NULL,               -- JSON: resolved scene or analysis request
    input_blob        BYTEA,                          -- analysis samples, f64 little-endian
    idempotency_key   TEXT    UNIQUE,
    request_hash      TEXT,
    label             TEXT    NOT NULL DEFAULT '',
    scene_key         TEXT,                           -- SHA-256 of the canonical scene (study sharing)
    progress          DOUBLE PRECISION NOT NULL DEFAULT 0,
    attempt           BIGINT  NOT NULL DEFAULT 0,     -- incremented by every claim; fences writes
    owner             TEXT,                           -- lease holder (worker id) while running
    lease_expires_at  BIGINT,                         -- unix ms
    cancel_requested  BOOLEAN NOT NULL DEFAULT FALSE,
    version           BIGINT  NOT NULL DEFAULT 1,     -- bumped by every visible change (ETag)
    created_at        BIGINT  NOT NULL,
    started_at        BIGINT,
    finished_at       BIGINT,
    updated_at        BIGINT  NOT NULL,
    error             TEXT,                           -- JSON {kind, message}
    stats             TEXT,                           -- JSON solver statistics
    result            TEXT                            -- JSON result summary
);
-- The queue: claims read the oldest queued row, FOR UPDATE SKIP LOCKED.
CREATE INDEX jobs_queued_seq ON jobs (seq) WHERE state = 'queued';
CREATE INDEX jobs_state_seq ON jobs (state, seq);
CREATE INDEX jobs_running_lease ON jobs (lease_expires_at) WHERE state = 'running';
CREATE INDEX jobs_scene_key ON jobs (scene_key);
CREATE INDEX jobs_tenant_seq ON jobs (tenant, seq);

-- Large outputs of a finished job: channels and spectra as little-endian f32, with JSON metadata.
CREATE TABLE artifacts (
    job_id TEXT  NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    name   TEXT  NOT NULL,
    meta   TEXT  NOT NULL,
    data   BYTEA NOT NULL,
    PRIMARY KEY (job_id, name)
);

CREATE TABLE studies (
    seq               BIGINT  GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
    id                TEXT    NOT NULL UNIQUE,
    tenant            TEXT    NOT NULL DEFAULT '',
    label             TEXT    NOT NULL,
    request           TEXT    NOT NULL,               -- JSON: the study request as accepted
    design            TEXT    NOT NULL,               -- JSON: the design's shape (factors, lines)
    cancel_requested  BOOLEAN NOT NULL DEFAULT FALSE,
    version           BIGINT  NOT NULL DEFAULT 1,
    created_at        BIGINT  NOT NULL,
    updated_at        BIGINT  NOT NULL
);
CREATE INDEX studies_tenant_seq ON studies (tenant, seq);

CREATE TABLE study_points (
    study_id  TEXT    NOT NULL REFERENCES studies (id) ON DELETE CASCADE,
    idx       BIGINT  NOT NULL,
    job_id    TEXT    NOT NULL REFERENCES jobs (id),
    spec      TEXT    NOT NULL,                       -- JSON: fault case, factor values, duration
    PRIMARY KEY (study_id, idx)
);
CREATE INDEX study_points_job ON study_points (job_id);

-- Wake-ups: a job that becomes claimable (inserted queued, or put back in the queue by a
-- release or a lease recovery) notifies the channel every worker process LISTENs on.
-- Workers also poll, so a notification lost with a dropped connection costs a poll.
CREATE FUNCTION bearing_sim_notify_queued() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
    PERFORM pg_notify('bearing_sim_queue', '');
    RETURN NULL;
END;
$$;
CREATE TRIGGER jobs_inserted_queued AFTER INSERT ON jobs
    FOR EACH ROW WHEN (NEW.state = 'queued') EXECUTE FUNCTION bearing_sim_notify_queued();
CREATE TRIGGER jobs_requeued AFTER UPDATE OF state ON jobs
    FOR EACH ROW WHEN (NEW.state = 'queued' AND OLD.state <> 'queued')
    EXECUTE FUNCTION bearing_sim_notify_queued();
