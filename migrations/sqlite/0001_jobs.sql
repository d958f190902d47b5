-- Durable job queue. One row per submitted job; `seq` orders the queue and the listings.
CREATE TABLE jobs (
    seq               INTEGER PRIMARY KEY AUTOINCREMENT,
    id                TEXT    NOT NULL UNIQUE,
    kind              TEXT    NOT NULL,              -- simulation | analysis
    state             TEXT    NOT NULL,              -- queued | running | succeeded | failed | cancelled
    input             TEXT    NOT NULL,              -- JSON: resolved scene or analysis request
    input_blob        BLOB,                          -- analysis samples, f64 little-endian
    idempotency_key   TEXT    UNIQUE,
    request_hash      TEXT,
    label             TEXT    NOT NULL DEFAULT '',
    progress          REAL    NOT NULL DEFAULT 0,
    attempt           INTEGER NOT NULL DEFAULT 0,    -- incremented by every claim; fences writes
    owner             TEXT,                          -- lease holder (worker id) while running
    lease_expires_at  INTEGER,                       -- unix ms
    cancel_requested  INTEGER NOT NULL DEFAULT 0,
    version           INTEGER NOT NULL DEFAULT 1,    -- bumped by every visible change (ETag)
    created_at        INTEGER NOT NULL,
    started_at        INTEGER,
    finished_at       INTEGER,
    updated_at        INTEGER NOT NULL,
    error             TEXT,                          -- JSON {kind, message}
    stats             TEXT,                          -- JSON solver statistics
    result            TEXT                           -- JSON result summary
);
CREATE INDEX jobs_state_seq ON jobs (state, seq);

-- Large outputs of a finished job: channels and spectra as little-endian f32, with JSON metadata.
CREATE TABLE artifacts (
    job_id TEXT    NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    name   TEXT    NOT NULL,
    meta   TEXT    NOT NULL,
    data   BLOB    NOT NULL,
    PRIMARY KEY (job_id, name)
);
