-- Why a session failed, for operators (REST and viewer); and the start-ups in a row whose rebuild
-- of the same stored inputs (rebuild_seq: how many there were) began and never completed: a session
-- whose rebuild keeps taking the server down is quarantined instead of rebuilt again.
ALTER TABLE sessions ADD COLUMN failure TEXT;
ALTER TABLE sessions ADD COLUMN rebuilds BIGINT NOT NULL DEFAULT 0;
ALTER TABLE sessions ADD COLUMN rebuild_seq BIGINT NOT NULL DEFAULT 0;
