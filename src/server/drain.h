/* drain.h — a listening socket that lets no new connection into its queue while the daemon
 * takes the ones already there (its stop: server.c tc_server_quiesce). */
#ifndef TC_SERVER_DRAIN_H
#define TC_SERVER_DRAIN_H

/* From now on the listening socket fd drops every connection's first packet (a SYN without
 * ACK) and keeps all others: no new connection joins its queue (a client's connect is
 * retried, and refused once the socket is shut), while handshakes already under way complete
 * and queued connections are untouched. 0, or -1 with errno (setsockopt's). */
int tc_drain_refuse_new(int fd);

#endif
