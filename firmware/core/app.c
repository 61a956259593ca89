/* The device side of docs/protocol.md: frames with CRC-16/MODBUS and resync, idempotent requests,
 * the staged EEPROM write with COMMIT, START/STOP/STATUS, telemetry and events.
 * Answers are streamed byte by byte (no transmit buffer: RAM is the AVR's scarcest resource). */
#include <string.h>
#include "app.h"
#include "store.h"
#include "text.h"
#include "record.h"
#include "pgm.h"
#include "passport.h"
#include "protocol.h"

#define SYNC 0xA5
#define MAX_PAYLOAD 250
#define T_BOARD_FIRST 0x30       /* 0x30..0x3F: the board's own requests (hal_request) */
#define T_BOARD_LAST 0x3F
#define INTER_BYTE_MS 5
#define EVENT_RING 4

enum { ST_IDLE, ST_RUNNING, ST_PAUSED, ST_FINISHED };

typedef struct {
    uint32_t number;
    zc_event_t e;
} stored_event_t;

/* Messages sent from more than one place, stored once. */
static const char no_token[] PROGMEM = "no write transaction with this token";
static const char outside_eeprom[] PROGMEM = "offset/length outside the EEPROM";
static const char no_template[] PROGMEM = "no such start template (START_SHABLON)";
static const char busy[] PROGMEM = "a macro runs: the EEPROM is not written during a run (stop it first)";
static const char protection_prefix[] PROGMEM = "protection: ";

static const app_board_t *board;
static zc_run_t run;
static uint8_t rx[MAX_PAYLOAD + 6];
static uint16_t rx_n;
static uint32_t rx_last_ms;
static struct {
    uint8_t valid, type, seq;
    uint16_t crc;
} last;                                   /* the last request served, to answer a retry the same */
static uint32_t token, token_counter, committed_token;
static uint16_t committed_changed, committed_crc;
static uint8_t state = ST_IDLE, slot = NO_SLOT, task;
static uint32_t run_start_ms, last_tick_ms, events, next_telemetry_ms;
static uint8_t telemetry_hz = 5, device_seq;
static stored_event_t ring[EVENT_RING];
static uint16_t tx_crc;
static const char *protection;            /* in flash: the board's protection that ended the run */

/* -- sending --------------------------------------------------------------------------------- */

void app_tx(uint8_t b)
{
    tx_crc = zc_crc16(tx_crc, b);
    hal_uart_write(b);
}

#define tx app_tx
void app_tx16(uint16_t v) { tx((uint8_t)v); tx((uint8_t)(v >> 8)); }
#define tx16 app_tx16
static void tx32(uint32_t v) { tx16((uint16_t)v); tx16((uint16_t)(v >> 16)); }
static void tx_text(const char *s, uint8_t n) { while (n--) tx((uint8_t)*s++); }
static void tx_text_P(const char *s, uint8_t n) { while (n--) tx(pgm_read_byte(s++)); }
/* A frame's field as wide as protocol.h (the Python table) makes it: TX_FIELD(4) is tx32. */
#define TX_FIELD(bytes) TX_FIELD_(bytes)
#define TX_FIELD_(bytes) tx_##bytes
#define tx_1 tx
#define tx_2 tx16
#define tx_4 tx32

void app_tx_begin(uint8_t type, uint8_t seq, uint8_t len)
{
    hal_uart_write(SYNC);
    tx_crc = 0xFFFF;
    tx(len);
    tx(type);
    tx(seq);
}

#define tx_begin app_tx_begin
void app_tx_end(void)
{
    uint16_t crc = tx_crc;
    hal_uart_write((uint8_t)crc);
    hal_uart_write((uint8_t)(crc >> 8));
}

#define tx_end app_tx_end
static uint8_t text_len_P(const char *s) { return (uint8_t)strlen_P(s); }

/* message is in flash */
void app_error(uint8_t request_type, uint8_t seq, uint8_t code, const char *message)
{
    uint8_t n = text_len_P(message);
    tx_begin(T_ERROR, seq, (uint8_t)(2 + n));
    tx(request_type);
    tx(code);
    tx_text_P(message, n);
    tx_end();
}

#define send_error app_error
/* message is in RAM */
static void send_error_text(uint8_t request_type, uint8_t seq, uint8_t code, const char *message)
{
    uint8_t n = (uint8_t)strlen(message);
    tx_begin(T_ERROR, seq, (uint8_t)(2 + n));
    tx(request_type);
    tx(code);
    tx_text(message, n);
    tx_end();
}

/* -- events and telemetry ---------------------------------------------------------------------- */

/* The end reason: the board's protection (prefixed), else the core's. */
static uint8_t reason_text(char *out)
{
    uint8_t n;
    if (!protection)
        return zc_reason_text(&run, run.end_reason, run.end_offset, out);
    n = text_len_P(protection_prefix);
    memcpy_P(out, protection_prefix, n);
    strcpy_P(out + n, protection);
    return (uint8_t)(n + text_len_P(protection));
}

static void send_event(uint8_t type, uint8_t seq, uint32_t number, const zc_event_t *e)
{
    char detail[ZC_TEXT_MAX];
    uint8_t n = protection && (e->kind == ZC_EV_PHASE_END || e->kind == ZC_EV_FINISH) ? reason_text(detail)
                : zc_event_text(&run, e, detail), with_phase = e->kind == ZC_EV_PHASE_START ||
                e->kind == ZC_EV_PHASE_END, with_offset = with_phase || e->kind == ZC_EV_MUSIC ||
                e->kind == ZC_EV_LIGHT;
    /* EVENT's fields by name; protocol.h writes them in the table's order and widths */
#define EV_NUMBER number
#define EV_TIME_MS e->time_ms
#define EV_KIND (uint8_t)(e->kind - 1)
#define EV_SECTION (with_phase || e->kind == ZC_EV_SECTION ? e->section : SECTION_NONE)
#define EV_INDEX (with_phase ? e->index : 0)
#define EV_REPETITION (with_phase || e->kind == ZC_EV_SECTION ? e->repetition : 0)
#define EV_OFFSET (with_offset ? e->offset : NO_OFFSET)
#define TX_EVENT(name, bytes) TX_FIELD(bytes)(EV_##name);
    tx_begin(type, seq, (uint8_t)(EVENT_FIXED + n));
    EVENT_FIELDS(TX_EVENT)
    tx_text(detail, n);
    tx_end();
}

void zc_event(const zc_event_t *e)
{
    static const hal_output_t off = {HAL_OFF, 0, 0};
    stored_event_t *s = &ring[events % EVENT_RING];
    if (e->kind == ZC_EV_PHASE_END || e->kind == ZC_EV_FINISH)
        hal_output(&off);          /* before the commands after the phase run (a MUSIC, a CYCLE of them) */
    s->number = events;
    s->e = *e;
    send_event(T_EVENT, device_seq++, events++, e);
}

/* The factory start templates (data/start_templates.toml; a test holds them to it): number, then
 * the ZC_TEMPLATE_SIZE bytes GET_TEMPLATE sends. Stored at the first start. */
#define FACTORY_TEMPLATES 3
static const uint8_t factory_templates[FACTORY_TEMPLATES][1 + ZC_TEMPLATE_SIZE] PROGMEM = {
    {1, ZC_CHARGE, 1, 2000 & 0xFF, 2000 >> 8, 1000 & 0xFF, 1000 >> 8, 0, 0, 4},
    {2, ZC_CHARGE, 1, 2200 & 0xFF, 2200 >> 8, 2200 & 0xFF, 2200 >> 8, 0, 0, 3},
    {3, ZC_CHARGE, 1, 7000 & 0xFF, 7000 >> 8, 1750 & 0xFF, 1750 >> 8, 0, 0, 6},
};

ZC_NOINLINE uint8_t zc_template(uint8_t number, zc_start_t *s)
{
    uint8_t t[ZC_TEMPLATE_SIZE];
    if (!store_template(number, t))
        return 0;
    zc_template_apply(s, t);
    return 1;
}

static ZC_NOINLINE int16_t centi(int32_t micro) { return (int16_t)(micro / 10000L); }

static void send_telemetry(void)
{
    uint8_t live = state == ST_RUNNING || state == ST_PAUSED;
    int32_t mv = hal_pack_uv() / 1000L;
    /* TELEMETRY's fields by name; protocol.h writes them in the table's order and widths */
#define TM_TIME_MS (state == ST_IDLE ? 0 : run.time_ms)
#define TM_TASK task
#define TM_SECTION (live && run.active ? run.phase_section : SECTION_NONE)
#define TM_REPETITION (live ? run.phase_rep : 0)
#define TM_CYCLE (live ? run.phase_pass : 0)
#define TM_PHASE (live ? run.phase_index : 0)
#define TM_RUN (live ? run.run_no : 0)
#define TM_FLAGS (uint8_t)((live ? FLAG_RUNNING : 0) | (run.paused && live ? FLAG_PAUSED : 0) | \
                  (hal_battery_sensor() ? FLAG_SENSOR : 0))
#define TM_VOLTAGE_MV (uint16_t)(mv < 0 ? 0 : (mv > 0xFFFF ? 0xFFFF : mv))
#define TM_CURRENT_MA (uint32_t)(hal_current_ua() / 1000L)
#define TM_TEMP_C100 (uint16_t)(hal_battery_sensor() ? centi(hal_battery_uc()) : TEMP_UNKNOWN)
#define TM_HEATSINK_C100 (uint16_t)centi(hal_heatsink_uc())
#define TM_MAH10_IN (run.total_in.uah / 100)            /* 0.1 mAh */
#define TM_MAH10_OUT (run.total_out.uah / 100)
#define TX_TELEMETRY(name, bytes) TX_FIELD(bytes)(TM_##name);
    tx_begin(T_TELEMETRY, device_seq++, TELEMETRY_FIXED);
    TELEMETRY_FIELDS(TX_TELEMETRY)
    tx_end();
}

/* -- requests ------------------------------------------------------------------------------------ */

static uint16_t le16(const uint8_t *p) { return (uint16_t)(p[0] | (p[1] << 8)); }
static uint32_t le32(const uint8_t *p) { return le16(p) | ((uint32_t)le16(p + 2) << 16); }

static void identify(uint8_t seq)
{
    uint8_t m = text_len_P(board->model), f = text_len_P(board->firmware);
    tx_begin(T_IDENTIFY | RESPONSE, seq, (uint8_t)(26 + m + f));
    tx(PROTOCOL_VERSION);
    tx16(store_size());
    tx(MAX_DATA);
    tx32(board->max_charge_ma);
    tx16(board->max_charge_dw);
    tx32(board->max_discharge_ma);
    tx16(board->max_discharge_dw);
    tx32(board->max_mv);
    tx32(board->write_us_per_byte);
    tx(m);
    tx_text_P(board->model, m);
    tx(f);
    tx_text_P(board->firmware, f);
    tx_end();
}

static const char *start_error_text(uint8_t err)
{
    switch (err) {
    case ZC_ERR_INPUT_CURRENT: return PSTR("the macro takes a current at start (INPUT): give the current");
    case ZC_ERR_C_NEEDS_CAPACITY: return PSTR("a current in C needs the capacity: declare CAPACITY or give it at start");
    case ZC_ERR_INPUT_VOLTAGE: return PSTR("the macro takes a voltage at start (INPUT): give the voltage");
    case ZC_ERR_S_NEEDS_SERIES: return PSTR("a voltage per cell (S) needs the cell count: declare SERIES or give it at start");
    case ZC_ERR_NO_TEMPLATE: return no_template;
    default: return PSTR("training needs at least 1 repetition");
    }
}

static void answer_start(uint8_t seq)
{
    uint8_t n = (uint8_t)strlen((const char *)run.rec + 4);
    tx_begin(T_START | RESPONSE, seq, (uint8_t)(1 + n));
    tx(slot);
    tx_text((const char *)run.rec + 4, n);
    tx_end();
}

/* The battery's passport against the started run: refuses (and answers) when they conflict. */
static ZC_NOINLINE uint8_t lockout(uint8_t seq)
{
    uint8_t passport[PASSPORT_SIZE], found = zc_passport_read(passport);
    char why[MAX_PAYLOAD - 2];
    if (found == PASSPORT_NONE)
        return 0;
    if (found == PASSPORT_BAD) {
        send_error(T_START, seq, E_PASSPORT_CONFLICT, PSTR("the battery's passport does not read (magic or check)"));
    } else if (zc_passport_conflicts(&run, passport, why, sizeof why)) {
        send_error_text(T_START, seq, E_PASSPORT_CONFLICT, why);
    } else {
        return 0;
    }
    run.finished = 1;
    return 1;
}

/* The board's say at START (hal_run_start): its refusal answered to the PC, the sentence when the board
 * wrote one (on a stack of its own, left before the lockout's deeper one); the display's line, NULL to
 * start. */
static ZC_NOINLINE const char *board_start(uint8_t seq, uint8_t panel)
{
    char sentence[HAL_SENTENCE_MAX];
    uint8_t code = E_START_ERROR;
    const char *why;
    sentence[0] = 0;
    why = hal_run_start(run.rec, run.akk_type, run.series, run.capacity_mah, &code, sentence);
    if (why && !panel) {
        if (sentence[0])
            send_error_text(T_START, seq, code, sentence);
        else
            send_error(T_START, seq, code, why);
    }
    return why;
}

/* The run of slot `number` begins, once the battery's passport allows it. */
static const char *started(uint8_t seq, uint8_t number, uint8_t panel)
{
    if (lockout(seq))
        return PSTR("the battery's passport forbids this macro");
    slot = number;
    task = run.start.task;   /* after the start template */
    events = 0;
    if (!panel)
        answer_start(seq);
    state = ST_RUNNING;
    run_start_ms = last_tick_ms = hal_millis();
    /* the first tick's averages are the run's own: readings of the idle pack before START (up to the idle
     * latch's second) would dilute its current, and the charge counted in that tick with it */
    hal_measure_latch();
    zc_control(&run);
    return 0;
}

/* Starts slot p[0] with a START request's values (docs/protocol.md), while no run is on (a PC's START
 * during one is BUSY, the panel starts only when idle). A PC's START is answered; a panel's
 * (panel = 1) is not: both get the refusal's text (in flash), NULL once the run started. */
static const char *start(uint8_t seq, const uint8_t *p, uint8_t panel)
{
    zc_start_t s;
    uint16_t len;
    uint8_t err, code = E_START_ERROR;
    const char *why;
    hal_output_t off = {HAL_OFF, 0, 0};
    hal_output(&off);
    state = ST_IDLE;
    slot = NO_SLOT;
    protection = 0;
    len = store_record(p[0], run.rec);
    if (len == 0) {
        code = E_BAD_SLOT;
        why = PSTR("there is no such slot");
    } else if (len == 0xFFFF || zc_validate(run.rec, len)) {
        code = E_INVALID_RECORD;
        why = PSTR("the slot's record does not decode");
    } else {
        s.task = p[1] <= ZC_TRAIN ? p[1] : ZC_CHARGE;
        s.repetitions = p[2];
        s.capacity_mah = le16(p + 3) ? (int32_t)le16(p + 3) : ZC_NONE;
        s.current_ua = le16(p + 5) ? (int32_t)le16(p + 5) * 1000L : ZC_NONE;
        s.voltage_uv = le16(p + 7) ? (int32_t)le16(p + 7) * 1000L : ZC_NONE;
        s.series = p[9];
        s.sensor = p[10] != 0;
        s.template_no = 0;
        err = zc_start(&run, run.rec, len, &s, &board->core);
        if (!err) {
            why = board_start(seq, panel);
            return why ? why : started(seq, p[0], panel);
        }
        why = start_error_text(err);
    }
    if (!panel)
        send_error(T_START, seq, code, why);
    return why;
}

static ZC_NOINLINE void status(uint8_t seq)
{
    char reason[ZC_TEXT_MAX];
    uint8_t name_n = slot == NO_SLOT ? 0 : (uint8_t)strlen((const char *)run.rec + 4);
    uint8_t reason_n = state == ST_FINISHED ? reason_text(reason) : 0;
    tx_begin(T_STATUS | RESPONSE, seq, (uint8_t)(20 + name_n + reason_n));
    tx(state);
    tx(slot);
    tx(task);
    tx32(hal_millis());
    tx32(state == ST_IDLE ? 0 : run.time_ms);
    tx32(events);
    tx32(1);
    tx(name_n);
    tx_text((const char *)run.rec + 4, name_n);
    tx_text(reason, reason_n);
    tx_end();
}

/* Each request's payload length (docs/protocol.md): ANY_LEN takes any, AT_LEAST_6 a header of 6 and
 * data; UNKNOWN for a type that is no request. */
#define ANY_LEN 0xFD
#define AT_LEAST_6 0xFE
#define UNKNOWN 0xFF
static const uint8_t request_len[] PROGMEM = {
    /* 0x01 IDENTIFY .. 0x06 ABORT (BEGIN_WRITE: the host's nonce, or empty) */ 0, 3, ANY_LEN, AT_LEAST_6, 6, 4,
    /* 0x07 .. 0x0F */ UNKNOWN, UNKNOWN, UNKNOWN, UNKNOWN, UNKNOWN, UNKNOWN, UNKNOWN, UNKNOWN, UNKNOWN,
    /* 0x10 START .. 0x17 SET_TEMPLATE */ 11, 0, 0, 1, 4, 0, 1, 1 + ZC_TEMPLATE_SIZE,
    /* 0x18 .. 0x1F */ UNKNOWN, UNKNOWN, UNKNOWN, UNKNOWN, UNKNOWN, UNKNOWN, UNKNOWN, UNKNOWN,
    /* 0x20 PASSPORT: the battery judges the request */ ANY_LEN
};

static uint8_t expected_len(uint8_t type)
{
    if (type >= T_BOARD_FIRST && type <= T_BOARD_LAST)
        return ANY_LEN;               /* the board checks its own requests */
    return type >= T_IDENTIFY && type <= T_PASSPORT ? pgm_read_byte(&request_len[type - T_IDENTIFY]) : UNKNOWN;
}

static uint8_t known_type(uint8_t t)
{
    return expected_len(t) != UNKNOWN;
}

static void handle(uint8_t type, uint8_t seq, const uint8_t *p, uint8_t len, uint8_t retry)
{
    uint8_t want = expected_len(type);       /* parse() passes known types only */
    if (want == AT_LEAST_6 ? len < 6 : want != ANY_LEN && len != want) {
        send_error(type, seq, E_BAD_REQUEST, PSTR("the payload does not fit the request's layout"));
        return;
    }
    if (app_running() && (type == T_BEGIN_WRITE || type == T_WRITE_STAGE || type == T_COMMIT ||
                          type == T_SET_TEMPLATE)) {
        send_error(type, seq, E_BUSY, busy);
        return;
    }
    switch (type) {
    case T_IDENTIFY:
        identify(seq);
        return;
    case T_READ_EEPROM: {
        uint16_t at, off;
        off = le16(p);
        if (p[2] == 0 || p[2] > MAX_DATA || (uint32_t)off + p[2] > store_size()) {
            send_error(type, seq, E_BAD_RANGE, outside_eeprom);
            return;
        }
        tx_begin(T_READ_EEPROM | RESPONSE, seq, (uint8_t)(2 + p[2]));
        tx16(off);
        for (at = off; at < off + p[2]; at++)
            tx(store_read(at));
        tx_end();
        return;
    }
    case T_BEGIN_WRITE:
        if (!retry) {
            store_stage_begin();
            /* The host's random nonce is the token: a COMMIT of it repeated after a reconnect is answered
             * only by the unit that committed it (docs/protocol.md), not by another of its model. No RAM:
             * token and committed_token were there. An empty request (an older host) gets a counted one. */
            token = len >= 4 ? le32(p) : 0;
            if (!token)
                token = ++token_counter * 2654435761UL;
            if (!token)
                token = 1;
        }
        tx_begin(T_BEGIN_WRITE | RESPONSE, seq, 6);
        tx32(token);
        tx16(store_size());
        tx_end();
        return;
    case T_WRITE_STAGE: {
        uint16_t off, k;
        off = le16(p + 4);
        if (!token || le32(p) != token) {
            send_error(type, seq, E_BAD_TOKEN, no_token);
            return;
        }
        if (len - 6 > MAX_DATA || (uint32_t)off + (len - 6) > store_size()) {
            send_error(type, seq, E_BAD_RANGE, outside_eeprom);
            return;
        }
        for (k = 0; k < (uint16_t)(len - 6); k++)
            store_stage_write((uint16_t)(off + k), p[6 + k]);
        tx_begin(T_WRITE_STAGE | RESPONSE, seq, 3);
        tx16(off);
        tx((uint8_t)(len - 6));
        tx_end();
        return;
    }
    case T_COMMIT: {
        uint32_t t;
        t = le32(p);
        if (t && t == committed_token) {
            /* a retry whose answer was lost: committed already */
        } else if (!token || t != token) {
            send_error(type, seq, E_BAD_TOKEN, no_token);
            return;
        } else if (store_stage_crc() != le16(p + 4)) {
            send_error(type, seq, E_CRC_MISMATCH, PSTR("the staged image's CRC is not the host's; nothing written"));
            return;
        } else {
            committed_crc = le16(p + 4);
            committed_changed = store_commit();
            committed_token = token;
            token = 0;
        }
        tx_begin(T_COMMIT | RESPONSE, seq, 4);
        tx16(committed_changed);
        tx16(committed_crc);
        tx_end();
        return;
    }
    case T_ABORT:
        if (le32(p) == 0 || le32(p) == token)
            token = 0;
        tx_begin(T_ABORT | RESPONSE, seq, 0);
        tx_end();
        return;
    case T_START:
        if (retry && slot == p[0]) {
            answer_start(seq);
            return;
        }
        if (app_running()) {
            /* a START during a run would restart its time and capacity limits: a host could keep
             * them from ever firing */
            send_error(type, seq, E_BUSY, PSTR("a macro runs: stop it first"));
            return;
        }
        start(seq, p, 0);
        return;
    case T_STOP:
        app_stop();
        tx_begin(T_STOP | RESPONSE, seq, 1);
        tx(state);
        tx_end();
        return;
    case T_STATUS:
        status(seq);
        return;
    case T_SET_TELEMETRY_RATE:
        if (p[0] < 1 || p[0] > 50) {
            send_error(type, seq, E_BAD_RANGE, PSTR("the telemetry rate is 1..50 Hz"));
            return;
        }
        telemetry_hz = p[0];
        tx_begin(T_SET_TELEMETRY_RATE | RESPONSE, seq, 1);
        tx(telemetry_hz);
        tx_end();
        return;
    case T_GET_EVENT: {
        uint32_t number;
        number = le32(p);
        if (number >= events || events - number > EVENT_RING) {
            send_error(type, seq, E_BAD_RANGE, PSTR("no such event (the device keeps the last 4)"));
            return;
        }
        send_event(T_GET_EVENT | RESPONSE, seq, number, &ring[number % EVENT_RING].e);
        return;
    }
    case T_LIST_TEMPLATES: {
        uint8_t t[ZC_TEMPLATE_SIZE], held[STORE_TEMPLATES], k, n = 0;
        for (k = 1; k <= STORE_TEMPLATES; k++)
            if (store_template(k, t))
                held[n++] = k;
        tx_begin(T_LIST_TEMPLATES | RESPONSE, seq, n);
        tx_text((const char *)held, n);
        tx_end();
        return;
    }
    case T_SET_TEMPLATE:
        /* task 0..2, repetitions 1..255, capacity 0 (not given) or 2..65534 (StartTemplate's ranges) */
        if (p[0] < 1 || p[0] > STORE_TEMPLATES || p[1] > ZC_TRAIN || p[2] == 0 || le16(p + 3) == 1 ||
            le16(p + 3) == 0xFFFF) {
            send_error(type, seq, E_BAD_RANGE, PSTR("not a start template (1..16)"));
            return;
        }
        store_set_template(p[0], p + 1);
        /* answers what is stored, as GET_TEMPLATE */
        /* fall through */
    case T_GET_TEMPLATE: {
        uint8_t t[ZC_TEMPLATE_SIZE], k;
        if (!store_template(p[0], t)) {
            send_error(type, seq, E_NO_TEMPLATE, no_template);
            return;
        }
        tx_begin((uint8_t)(type | RESPONSE), seq, 1 + ZC_TEMPLATE_SIZE);
        tx(p[0]);
        for (k = 0; k < ZC_TEMPLATE_SIZE; k++)
            tx(t[k]);
        tx_end();
        return;
    }
    case T_PASSPORT: {
        uint8_t answer[32], k;
        if (!hal_passport_exchange(p, len, answer)) {
            send_error(type, seq, E_NO_PASSPORT, PSTR("the battery has no passport"));
            return;
        }
        tx_begin(T_PASSPORT | RESPONSE, seq, 32);
        for (k = 0; k < 32; k++)
            tx(answer[k]);
        tx_end();
        return;
    }
    default:
        hal_request(type, seq, p, len, app_running());
    }
}

static void drop(uint16_t n)
{
    memmove(rx, rx + n, rx_n - n);
    rx_n = (uint16_t)(rx_n - n);
}

static void parse(void)
{
    while (rx_n) {
        uint16_t need, crc = 0xFFFF, k;
        if (rx[0] != SYNC) {
            drop(1);
            continue;
        }
        if (rx_n < 3)
            return;
        if (rx[1] > MAX_PAYLOAD || !known_type(rx[2])) {
            drop(1);
            continue;
        }
        need = (uint16_t)(rx[1] + 6);
        if (rx_n < need)
            return;
        for (k = 1; k < need; k++)
            crc = zc_crc16(crc, rx[k]);
        if (crc != 0) {
            send_error(0, 0, E_BAD_FRAME, PSTR("bad frame"));
            drop(1);
            continue;
        }
        {
            uint16_t frame_crc = le16(rx + need - 2);
            uint8_t retry = last.valid && last.type == rx[2] && last.seq == rx[3] && last.crc == frame_crc;
            last.valid = 1;
            last.type = rx[2];
            last.seq = rx[3];
            last.crc = frame_crc;
            handle(rx[2], rx[3], rx + 4, rx[1], retry);
        }
        drop(need);
    }
}

void app_init(const app_board_t *b)
{
    board = b;
    if (store_init()) {
        uint8_t k, t[1 + ZC_TEMPLATE_SIZE];
        for (k = 0; k < FACTORY_TEMPLATES; k++) {
            memcpy_P(t, factory_templates[k], sizeof t);
            store_set_template(t[0], t + 1);
        }
    }
    memset(&run, 0, sizeof run);
    run.finished = 1;
}

void app_poll(void)
{
    int16_t c;
    uint32_t now = hal_millis();
    uint8_t got = 0;
    while ((c = hal_uart_read()) >= 0 && rx_n < sizeof rx) {
        rx[rx_n++] = (uint8_t)c;
        got = 1;
    }
    if (got) {
        rx_last_ms = now;
        parse();
    } else if (rx_n && now - rx_last_ms > INTER_BYTE_MS) {
        drop(1);               /* a frame the line left unfinished: resync past its sync byte */
        parse();
    }
    /* signed: a START served in this poll may have set last_tick_ms after `now` was read */
    if (app_running() && (int32_t)(now - last_tick_ms) >= (int32_t)board->core.tick_ms) {
        last_tick_ms += board->core.tick_ms;
        hal_measure_latch();
        zc_measure(&run);
        if (!run.finished)
            zc_control(&run);
        state = run.finished ? ST_FINISHED : (run.paused ? ST_PAUSED : ST_RUNNING);
    }
    if ((int32_t)(now - next_telemetry_ms) >= 0) {
        next_telemetry_ms = now + 1000UL / telemetry_hz;
        send_telemetry();
    }
}

/* A listener on TX alone (docs/protocol.md, *Listen-only*) gets the LCD's lines too; a host that has
 * spoken asks for what it wants, so it gets none (a 16-column line straight from the panel's copy). */
void app_lcd(uint8_t row, const char *text)
{
    uint8_t k;
    if (last.valid)
        return;
    tx_begin(T_LCD, device_seq++, 1 + APP_LCD_COLUMNS);
    tx(row);
    for (k = 0; k < APP_LCD_COLUMNS; k++)
        tx(*text ? (uint8_t)*text++ : ' ');
    tx_end();
}

uint8_t app_running(void) { return state == ST_RUNNING || state == ST_PAUSED; }
uint8_t app_state(void) { return state; }
const zc_run_t *app_run(void) { return &run; }
uint8_t app_end_text(char *out) { return reason_text(out); }

const char *app_start_slot(uint8_t number, uint8_t series, uint16_t current_ma)
{
    uint8_t p[11];
    memset(p, 0, sizeof p);
    p[0] = number;
    p[2] = 1;
    p[5] = (uint8_t)current_ma;
    p[6] = (uint8_t)(current_ma >> 8);
    p[9] = series;
    p[10] = 1;
    return start(0, p, 1);
}

void app_stop(void)
{
    if (app_running()) {
        zc_stop(&run);
        state = ST_FINISHED;
    }
}

void app_protect(const char *text)
{
    hal_output_t off = {HAL_OFF, 0, 0};
    hal_output(&off);
    protection = text;
    if (app_running()) {
        zc_stop(&run);
    } else {
        /* no run to end (a watchdog reset lost it): the reason still goes out as a finish event */
        zc_event_t e;
        memset(&e, 0, sizeof e);
        e.kind = ZC_EV_FINISH;
        e.time_ms = run.time_ms;
        events = 0;
        zc_event(&e);
    }
    state = ST_FINISHED;
}
