//! A mock OpenAI-compatible server on loopback, for tests and `bench llm`.
//!
//! Input: a script of [`MockReply`] behaviours (used in order, one per request) and a responder
//! for requests past the script (by default a fixed completion), plus a per-request latency.
//! Output: a server on `127.0.0.1:<free port>` whose [`MockServer::base_url`] a
//! [`super::ClientConfig`] points at, and what it saw: every request ([`MockRequest`]: path,
//! headers, body; the `Authorization` value only as a hash), the largest number of requests in
//! flight at once, and the body bytes it streamed.
//!
//! Behaviours cover what a real endpoint does on a bad day: errors with `Retry-After`, a response
//! that never comes, bodies that are not JSON or not a completion, a 20 MB body, and a connection
//! closed without an answer. The server runs on the caller's tokio runtime and stops when the
//! `MockServer` is dropped. It binds loopback only; no test reaches any other address.

use std::collections::VecDeque;
use std::convert::Infallible;
use std::net::{Ipv4Addr, SocketAddr};
use std::pin::Pin;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::task::{Context, Poll};
use std::time::Duration;

use bytes::Bytes;
use http_body::{Frame, SizeHint};
use http_body_util::combinators::BoxBody;
use http_body_util::{BodyExt as _, Full};
use hyper::body::Incoming;
use hyper::server::conn::http1;
use hyper::service::service_fn;
use hyper::{Request, Response, StatusCode};
use hyper_util::rt::TokioIo;
use serde_json::{Value, json};
use tokio::net::TcpListener;
use tokio::task::{JoinHandle, JoinSet};

use super::types::TokenUsage;
use crate::util::content_hash;

/// The model the mock lists by default.
pub const MOCK_MODEL: &str = "mock-model";

/// Chunk size of streamed large bodies.
const STREAM_CHUNK_BYTES: usize = 64 * 1024;

/// The body of [`MockReply::Malformed`]: a completion cut off mid-string, so not JSON.
const MALFORMED_BODY: &str = "{\"choices\": [{\"message\": {\"content\": \"unterminated";

/// What the mock does with one request.
#[derive(Debug, Clone, PartialEq)]
pub enum MockReply {
    /// 200 with a chat completion.
    Ok {
        /// The assistant message.
        content: String,
        /// Reported usage; `None` computes one from the request and content lengths.
        usage: Option<TokenUsage>,
        /// Reported model; `None` echoes the requested one.
        model: Option<String>,
    },
    /// Any status with a body and headers (e.g. `Retry-After`).
    Status {
        /// The HTTP status.
        status: u16,
        /// The body, sent as `application/json`.
        body: String,
        /// Extra headers.
        headers: Vec<(String, String)>,
    },
    /// Never answers (until the client gives up or the server is dropped).
    Hang,
    /// 200 with a body that is not JSON.
    Malformed,
    /// 200 with a JSON body whose `choices` list is empty.
    NoChoices,
    /// 200 with a completion whose content is `null`.
    NullContent,
    /// 200 with a body of `bytes` bytes, streamed in chunks; with `declare_length` the
    /// `Content-Length` header announces the size, otherwise it is chunked.
    Huge {
        /// Body size.
        bytes: u64,
        /// Whether to send `Content-Length`.
        declare_length: bool,
    },
    /// Closes the connection without answering.
    Close,
    /// Waits, then behaves as `then` (on top of the server's latency).
    Delayed {
        /// Extra wait.
        delay: Duration,
        /// The behaviour after the wait.
        then: Box<MockReply>,
    },
}

impl MockReply {
    /// 200 with `content`, usage computed from lengths, the requested model echoed.
    pub fn ok(content: impl Into<String>) -> Self {
        MockReply::Ok {
            content: content.into(),
            usage: None,
            model: None,
        }
    }

    /// 200 with `content` and the given usage.
    pub fn ok_with_usage(content: impl Into<String>, usage: TokenUsage) -> Self {
        MockReply::Ok {
            content: content.into(),
            usage: Some(usage),
            model: None,
        }
    }

    /// `status` with an OpenAI-style error body (`{"error": {"message", "type", "code"}}`).
    pub fn error(status: u16, message: &str, code: Option<&str>) -> Self {
        MockReply::Status {
            status,
            body: json!({"error": {"message": message, "type": code, "code": code}}).to_string(),
            headers: Vec::new(),
        }
    }

    /// 429 with `Retry-After: <retry_after>`.
    pub fn rate_limited(retry_after: &str) -> Self {
        MockReply::error(
            429,
            "Rate limit reached for requests",
            Some("rate_limit_exceeded"),
        )
        .with_header("retry-after", retry_after)
    }

    /// This reply with one more header (only `Status` replies carry headers).
    #[must_use]
    pub fn with_header(mut self, name: &str, value: &str) -> Self {
        if let MockReply::Status { headers, .. } = &mut self {
            headers.push((name.to_owned(), value.to_owned()));
        }
        self
    }

    /// This reply after an extra `delay`.
    #[must_use]
    pub fn delayed(self, delay: Duration) -> Self {
        MockReply::Delayed {
            delay,
            then: Box::new(self),
        }
    }
}

/// One request as the mock saw it.
#[derive(Debug, Clone)]
pub struct MockRequest {
    /// Arrival order, from 0.
    pub index: u64,
    /// HTTP method.
    pub method: String,
    /// Request path, e.g. `/v1/chat/completions`.
    pub path: String,
    /// Headers with lowercase names, `authorization` left out (see [`MockRequest::has_authorization`]).
    pub headers: Vec<(String, String)>,
    /// blake3 of the `Authorization` value: tests can check it without the mock keeping a key.
    authorization_hash: Option<String>,
    /// The body as text (lossy UTF-8).
    pub body: String,
    /// The body as JSON, when it is.
    pub json: Option<Value>,
    /// When the request's head arrived (wall clock, for rate measurements).
    pub received_at: std::time::Instant,
}

impl MockRequest {
    /// Whether the request carried an `Authorization` header.
    pub fn has_authorization(&self) -> bool {
        self.authorization_hash.is_some()
    }

    /// Whether the `Authorization` header was exactly `expected`.
    pub fn authorization_is(&self, expected: &str) -> bool {
        self.authorization_hash.as_deref() == Some(content_hash(expected.as_bytes()).as_str())
    }

    /// The first value of header `name` (lowercase).
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(header, _)| header == name)
            .map(|(_, value)| value.as_str())
    }

    /// The requested model.
    pub fn model(&self) -> Option<&str> {
        self.json.as_ref()?.get("model")?.as_str()
    }

    /// The text of the last `user` message of a chat request.
    pub fn last_user_text(&self) -> Option<&str> {
        self.json
            .as_ref()?
            .get("messages")?
            .as_array()?
            .iter()
            .rev()
            .find(|message| message.get("role").and_then(Value::as_str) == Some("user"))?
            .get("content")?
            .as_str()
    }
}

/// Chooses the reply to a request once the script is used up.
pub type Responder = Arc<dyn Fn(&MockRequest) -> MockReply + Send + Sync>;

/// How to start a [`MockServer`].
pub struct MockServerBuilder {
    models: Vec<String>,
    latency: Duration,
    script: Vec<MockReply>,
    responder: Responder,
}

impl MockServerBuilder {
    /// Time the server waits before each reply. Default none.
    #[must_use]
    pub fn latency(mut self, latency: Duration) -> Self {
        self.latency = latency;
        self
    }

    /// The model ids `GET /models` lists. Default: [`MOCK_MODEL`]. Chat requests are answered
    /// whatever model they name; the list is what a preflight check sees.
    #[must_use]
    pub fn models(mut self, models: impl IntoIterator<Item = impl Into<String>>) -> Self {
        self.models = models.into_iter().map(Into::into).collect();
        self
    }

    /// Replies for the first requests, in order.
    #[must_use]
    pub fn script(mut self, replies: impl IntoIterator<Item = MockReply>) -> Self {
        self.script.extend(replies);
        self
    }

    /// Chooses the reply for requests past the script. Default: `MockReply::ok("mock completion")`.
    #[must_use]
    pub fn responder(
        mut self,
        responder: impl Fn(&MockRequest) -> MockReply + Send + Sync + 'static,
    ) -> Self {
        self.responder = Arc::new(responder);
        self
    }

    /// Answers each chat request with `answer(text of its last user message)`; a request without
    /// one gets a 400.
    #[must_use]
    pub fn answering(self, answer: impl Fn(&str) -> String + Send + Sync + 'static) -> Self {
        self.responder(move |request| match request.last_user_text() {
            Some(text) => MockReply::ok(answer(text)),
            None => MockReply::error(400, "the request has no user message", None),
        })
    }

    /// Binds `127.0.0.1:0` and starts serving on the current tokio runtime.
    pub async fn start(self) -> std::io::Result<MockServer> {
        let listener = TcpListener::bind((Ipv4Addr::LOCALHOST, 0)).await?;
        let address = listener.local_addr()?;
        let state = Arc::new(MockState {
            latency: self.latency,
            script: Mutex::new(self.script.into()),
            responder: self.responder,
            requests: Mutex::new(Vec::new()),
            next_index: AtomicU64::new(0),
            in_flight: AtomicUsize::new(0),
            max_in_flight: AtomicUsize::new(0),
            body_bytes_sent: Arc::new(AtomicU64::new(0)),
            models: self.models,
        });
        let accept_task = tokio::spawn(accept_loop(listener, Arc::clone(&state)));
        Ok(MockServer {
            address,
            state,
            accept_task,
        })
    }
}

/// A running mock server; dropping it stops it and closes its connections.
pub struct MockServer {
    address: SocketAddr,
    state: Arc<MockState>,
    accept_task: JoinHandle<()>,
}

impl std::fmt::Debug for MockServer {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        formatter
            .debug_struct("MockServer")
            .field("address", &self.address)
            .finish_non_exhaustive()
    }
}

impl MockServer {
    /// A builder with no latency, no script and the default responder.
    pub fn builder() -> MockServerBuilder {
        MockServerBuilder {
            models: vec![MOCK_MODEL.to_owned()],
            latency: Duration::ZERO,
            script: Vec::new(),
            responder: Arc::new(|_| MockReply::ok("mock completion")),
        }
    }

    /// A server that plays `script`, then answers with the default completion.
    pub async fn scripted(script: impl IntoIterator<Item = MockReply>) -> std::io::Result<Self> {
        MockServer::builder().script(script).start().await
    }

    /// The socket address the server listens on.
    pub fn address(&self) -> SocketAddr {
        self.address
    }

    /// The base URL for a client: `http://127.0.0.1:<port>/v1`.
    pub fn base_url(&self) -> String {
        format!("http://{}/v1", self.address)
    }

    /// Every request received so far, in arrival order.
    pub fn requests(&self) -> Vec<MockRequest> {
        let mut requests = lock(&self.state.requests).clone();
        requests.sort_by_key(|request| request.index);
        requests
    }

    /// Requests received so far.
    pub fn request_count(&self) -> usize {
        lock(&self.state.requests).len()
    }

    /// The most requests that were in flight (received, not yet answered) at one time.
    pub fn max_in_flight(&self) -> usize {
        self.state.max_in_flight.load(Ordering::SeqCst)
    }

    /// Body bytes handed to the connection by `Huge` replies so far.
    pub fn body_bytes_sent(&self) -> u64 {
        self.state.body_bytes_sent.load(Ordering::SeqCst)
    }
}

impl Drop for MockServer {
    fn drop(&mut self) {
        // The accept task owns the connection tasks; aborting it drops (aborts) them all.
        self.accept_task.abort();
    }
}

struct MockState {
    latency: Duration,
    script: Mutex<VecDeque<MockReply>>,
    responder: Responder,
    requests: Mutex<Vec<MockRequest>>,
    next_index: AtomicU64,
    in_flight: AtomicUsize,
    max_in_flight: AtomicUsize,
    body_bytes_sent: Arc<AtomicU64>,
    models: Vec<String>,
}

fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    // Test-double state: a panic elsewhere must not hide what was recorded.
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Counts a request as in flight from its arrival until its reply is done or abandoned.
struct InFlight(Arc<MockState>);

impl InFlight {
    fn enter(state: &Arc<MockState>) -> Self {
        let now = state.in_flight.fetch_add(1, Ordering::SeqCst) + 1;
        state.max_in_flight.fetch_max(now, Ordering::SeqCst);
        InFlight(Arc::clone(state))
    }
}

impl Drop for InFlight {
    fn drop(&mut self) {
        self.0.in_flight.fetch_sub(1, Ordering::SeqCst);
    }
}

async fn accept_loop(listener: TcpListener, state: Arc<MockState>) {
    let mut connections = JoinSet::new();
    loop {
        tokio::select! {
            accepted = listener.accept() => match accepted {
                Ok((stream, _peer)) => {
                    let _ = stream.set_nodelay(true);
                    let state = Arc::clone(&state);
                    connections.spawn(async move {
                        let service = service_fn(move |request| handle(Arc::clone(&state), request));
                        // A connection error (including the deliberate `Close`) ends only it.
                        let _ = http1::Builder::new()
                            .serve_connection(TokioIo::new(stream), service)
                            .await;
                    });
                }
                // Out of file descriptors and the like: wait rather than spin.
                Err(_) => tokio::time::sleep(Duration::from_millis(10)).await,
            },
            Some(_finished) = connections.join_next(), if !connections.is_empty() => {}
        }
    }
}

type MockBody = BoxBody<Bytes, Infallible>;

/// Serves one request: records it, answers `GET /models` and unknown routes as a real endpoint
/// would, and chat completions with the next scripted reply (or the responder's).
async fn handle(
    state: Arc<MockState>,
    request: Request<Incoming>,
) -> Result<Response<MockBody>, std::io::Error> {
    let _in_flight = InFlight::enter(&state);
    let received_at = std::time::Instant::now();
    let (parts, body) = request.into_parts();
    let body = body
        .collect()
        .await
        .map_err(std::io::Error::other)?
        .to_bytes();
    let recorded = record(&state, &parts, &body, received_at);
    if let Some(response) = route(&state, &parts.method, &recorded) {
        return Ok(response);
    }
    let reply = next_reply(&state, &recorded).await;
    respond(&state, &recorded, reply).await
}

/// Records the request (headers lowercase, the `Authorization` value only as a hash) and
/// returns what was recorded.
fn record(
    state: &MockState,
    parts: &hyper::http::request::Parts,
    body: &Bytes,
    received_at: std::time::Instant,
) -> MockRequest {
    let mut headers = Vec::new();
    let mut authorization_hash = None;
    for (name, value) in &parts.headers {
        if name == hyper::header::AUTHORIZATION {
            authorization_hash = Some(content_hash(value.as_bytes()));
        } else {
            headers.push((
                name.as_str().to_owned(),
                String::from_utf8_lossy(value.as_bytes()).into_owned(),
            ));
        }
    }
    let recorded = MockRequest {
        index: state.next_index.fetch_add(1, Ordering::SeqCst),
        method: parts.method.as_str().to_owned(),
        path: parts.uri.path().to_owned(),
        headers,
        authorization_hash,
        body: String::from_utf8_lossy(body).into_owned(),
        json: serde_json::from_slice(body).ok(),
        received_at,
    };
    lock(&state.requests).push(recorded.clone());
    recorded
}

/// The answer to anything but a chat completion: the model list for `GET /models`, a 404 for a
/// route a real endpoint does not have; `None` for a chat completion.
fn route(
    state: &MockState,
    method: &hyper::Method,
    recorded: &MockRequest,
) -> Option<Response<MockBody>> {
    if *method == hyper::Method::GET && matches!(recorded.path.as_str(), "/v1/models" | "/models") {
        let data: Vec<Value> = state
            .models
            .iter()
            .map(|id| json!({"id": id, "object": "model", "owned_by": "mock"}))
            .collect();
        return Some(json_response(
            200,
            &json!({"object": "list", "data": data}).to_string(),
            &[],
        ));
    }
    // The routes of a real endpoint: a base URL with a wrong path gets a 404 as it would there.
    if *method != hyper::Method::POST
        || !matches!(
            recorded.path.as_str(),
            "/v1/chat/completions" | "/chat/completions"
        )
    {
        return Some(json_response(
            404,
            &json!({"error": {"message": format!("no route for {} {}", recorded.method, recorded.path), "code": "not_found"}})
                .to_string(),
            &[],
        ));
    }
    None
}

/// The reply to a chat completion: the next scripted one, else the responder's; after the
/// server's latency and any delays the reply asks for.
async fn next_reply(state: &MockState, recorded: &MockRequest) -> MockReply {
    let scripted = lock(&state.script).pop_front();
    let mut reply = scripted.unwrap_or_else(|| (state.responder)(recorded));
    tokio::time::sleep(state.latency).await;
    while let MockReply::Delayed { delay, then } = reply {
        tokio::time::sleep(delay).await;
        reply = *then;
    }
    reply
}

/// The response `reply` makes to `recorded`.
async fn respond(
    state: &MockState,
    recorded: &MockRequest,
    reply: MockReply,
) -> Result<Response<MockBody>, std::io::Error> {
    match reply {
        MockReply::Ok {
            content,
            usage,
            model,
        } => {
            let usage = usage.unwrap_or_else(|| {
                let prompt_tokens = (recorded.body.len() / 4) as u64;
                let completion_tokens = (content.len() / 4) as u64 + 1;
                TokenUsage {
                    prompt_tokens,
                    completion_tokens,
                    total_tokens: prompt_tokens + completion_tokens,
                }
            });
            let model = model.or_else(|| recorded.model().map(str::to_owned));
            let body = completion_body(
                recorded.index,
                &Value::from(content),
                model.as_deref(),
                usage,
            );
            Ok(json_response(200, &body.to_string(), &[]))
        }
        MockReply::NullContent => {
            let body = completion_body(
                recorded.index,
                &Value::Null,
                recorded.model(),
                TokenUsage::default(),
            );
            Ok(json_response(200, &body.to_string(), &[]))
        }
        MockReply::NoChoices => Ok(json_response(
            200,
            &json!({"id": "mock", "object": "chat.completion", "choices": []}).to_string(),
            &[],
        )),
        MockReply::Malformed => Ok(json_response(200, MALFORMED_BODY, &[])),
        MockReply::Status {
            status,
            body,
            headers,
        } => Ok(json_response(status, &body, &headers)),
        MockReply::Huge {
            bytes,
            declare_length,
        } => {
            let body = RepeatBody {
                remaining: bytes,
                declared: declare_length,
                chunk: Bytes::from(vec![b' '; STREAM_CHUNK_BYTES]),
                sent: Arc::clone(&state.body_bytes_sent),
            };
            let mut response = Response::new(body.boxed());
            response.headers_mut().insert(
                hyper::header::CONTENT_TYPE,
                hyper::header::HeaderValue::from_static("application/json"),
            );
            Ok(response)
        }
        MockReply::Hang => std::future::pending().await,
        MockReply::Close => Err(std::io::Error::other("the mock closes the connection")),
        // Unwrapped by the loop above.
        MockReply::Delayed { .. } => Err(std::io::Error::other("nested delay")),
    }
}

fn completion_body(index: u64, content: &Value, model: Option<&str>, usage: TokenUsage) -> Value {
    json!({
        "id": format!("chatcmpl-mock-{index}"),
        "object": "chat.completion",
        "created": 0,
        "model": model,
        "system_fingerprint": "fp_mock",
        "choices": [{
            "index": 0,
            "message": {"role": "assistant", "content": content},
            "logprobs": null,
            "finish_reason": "stop"
        }],
        "usage": {
            "prompt_tokens": usage.prompt_tokens,
            "completion_tokens": usage.completion_tokens,
            "total_tokens": usage.total_tokens
        }
    })
}

fn json_response(status: u16, body: &str, headers: &[(String, String)]) -> Response<MockBody> {
    let mut response = Response::new(Full::new(Bytes::from(body.to_owned())).boxed());
    *response.status_mut() =
        StatusCode::from_u16(status).unwrap_or(StatusCode::INTERNAL_SERVER_ERROR);
    let response_headers = response.headers_mut();
    response_headers.insert(
        hyper::header::CONTENT_TYPE,
        hyper::header::HeaderValue::from_static("application/json"),
    );
    for (name, value) in headers {
        if let (Ok(name), Ok(value)) = (
            hyper::header::HeaderName::from_bytes(name.as_bytes()),
            hyper::header::HeaderValue::from_str(value),
        ) {
            response_headers.append(name, value);
        }
    }
    response
}

/// A body of `remaining` bytes produced chunk by chunk, never held whole in memory.
struct RepeatBody {
    remaining: u64,
    declared: bool,
    chunk: Bytes,
    sent: Arc<AtomicU64>,
}

impl http_body::Body for RepeatBody {
    type Data = Bytes;
    type Error = Infallible;

    fn poll_frame(
        self: Pin<&mut Self>,
        _context: &mut Context<'_>,
    ) -> Poll<Option<Result<Frame<Bytes>, Infallible>>> {
        let this = self.get_mut();
        if this.remaining == 0 {
            return Poll::Ready(None);
        }
        let length = usize::try_from(this.remaining)
            .unwrap_or(usize::MAX)
            .min(this.chunk.len());
        this.remaining -= length as u64;
        this.sent.fetch_add(length as u64, Ordering::SeqCst);
        Poll::Ready(Some(Ok(Frame::data(this.chunk.slice(..length)))))
    }

    fn is_end_stream(&self) -> bool {
        self.remaining == 0
    }

    fn size_hint(&self) -> SizeHint {
        if self.declared {
            SizeHint::with_exact(self.remaining)
        } else {
            SizeHint::default()
        }
    }
}
