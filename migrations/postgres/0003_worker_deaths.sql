-- Telling a worker's death apart from a job that kills its worker (src/store/sql/queue.rs,
-- recover_expired): the progress the current attempt reported, the best progress when it
-- was claimed, and the worker deaths in a row in which the job got no further.
-- (migrations/sqlite/0005 on the embedded backend.)
ALTER TABLE jobs ADD COLUMN attempt_progress DOUBLE PRECISION NOT NULL DEFAULT 0;
ALTER TABLE jobs ADD COLUMN claim_progress DOUBLE PRECISION NOT NULL DEFAULT 0;
ALTER TABLE jobs ADD COLUMN worker_deaths BIGINT NOT NULL DEFAULT 0;
