-- Parameter studies: a study is a list of points, each point a simulation job. Identical
-- scenes share one job, found by the SHA-256 of their canonical JSON (jobs.scene_key).
ALTER TABLE jobs ADD COLUMN scene_key TEXT;
CREATE INDEX jobs_scene_key ON jobs (scene_key);

CREATE TABLE studies (
    seq               INTEGER PRIMARY KEY AUTOINCREMENT,
    id                TEXT    NOT NULL UNIQUE,
    label             TEXT    NOT NULL,
    request           TEXT    NOT NULL,              -- JSON: the study request as accepted
    design            TEXT    NOT NULL,              -- JSON: the design's shape (factors, lines)
    cancel_requested  INTEGER NOT NULL DEFAULT 0,
    version           INTEGER NOT NULL DEFAULT 1,    -- bumped by the study's own changes
    created_at        INTEGER NOT NULL,
    updated_at        INTEGER NOT NULL
);

CREATE TABLE study_points (
    study_id  TEXT    NOT NULL REFERENCES studies (id) ON DELETE CASCADE,
    idx       INTEGER NOT NULL,
    job_id    TEXT    NOT NULL REFERENCES jobs (id),
    spec      TEXT    NOT NULL,                      -- JSON: fault case, factor values, duration
    PRIMARY KEY (study_id, idx)
);
CREATE INDEX study_points_job ON study_points (job_id);
